#!/usr/bin/env bash
# Installs dependencies (scripts/setup.sh), configures and builds Ripple into
# build/ with two jobs. Extra arguments go to cmake's configure step.
# Under CI=true the libraries are unity-built (a fresh build is faster; an
# edit recompiles more, so not by default). RIPPLE_TIME_LOG=FILE logs each
# compile's and link's seconds there (scripts/ci/time_launcher.sh).
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
args=()
[[ ${CI:-} == true ]] && args+=(-DRIPPLE_UNITY_BUILD=ON)
if [[ -n ${RIPPLE_TIME_LOG:-} ]]; then
  t=$PWD/scripts/ci/time_launcher.sh
  args+=(-DCMAKE_CXX_COMPILER_LAUNCHER="$t" -DCMAKE_C_COMPILER_LAUNCHER="$t"
         -DCMAKE_CXX_LINKER_LAUNCHER="$t")
fi
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "${args[@]}" "$@" >/dev/null
cmake --build build -j"${RIPPLE_JOBS:-2}"
