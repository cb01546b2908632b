#!/usr/bin/env bash
# Installs dependencies (scripts/setup.sh), configures and builds Ripple into
# build/ with two jobs. Extra arguments go to cmake's configure step.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
cmake -S . -B build -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build -j"${RIPPLE_JOBS:-2}"
