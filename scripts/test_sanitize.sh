#!/usr/bin/env bash
# The sanitizer run of CI: builds Ripple with clang, AddressSanitizer and
# UBSan (-fno-sanitize-recover: any report fails) and the libFuzzer targets
# into build-asan/, runs the whole test suite under it, then each fuzzer for
# a bounded time (FUZZ_SECONDS, default 20) on its seed corpus. Extra
# arguments go to cmake's configure step.
# Leak reports inside Mesa, fontconfig and libusb are suppressed
# (scripts/sanitizer/lsan.supp); any other leak fails.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
launcher=()
if [[ -n ${RIPPLE_TIME_LOG:-} ]]; then
  # Seconds per compile and link (scripts/ci/build_times.py sums them).
  t=$ROOT/scripts/ci/time_launcher.sh
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER="$t" -DCMAKE_CXX_COMPILER_LAUNCHER="$t"
            -DCMAKE_CXX_LINKER_LAUNCHER="$t")
elif command -v ccache >/dev/null; then
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
# -O1: the sanitizers' usual level (fast enough to run the tests, quick to
# build). -gline-tables-only: file and line for every frame of a report
# (function names come from the symbol table), without the type and variable
# information of -g that makes compiles and links slower. lld links faster
# than ld.bfd. No benchmarks (not run by ctest). Build times:
# docs/reliability.md, "Build time".
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" \
  -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -gline-tables-only" \
  -DCMAKE_EXE_LINKER_FLAGS=-fuse-ld=lld \
  -DRIPPLE_SANITIZE=ON -DRIPPLE_FUZZ=ON -DRIPPLE_BUILD_BENCHMARKS=OFF \
  -DRIPPLE_UNITY_BUILD=ON "${launcher[@]}" "$@" >/dev/null
cmake --build build-asan -j"${RIPPLE_JOBS:-2}"
source scripts/sanitizer/env.sh
cd build-asan
if command -v xvfb-run >/dev/null && [[ -z "${DISPLAY:-}" ]]; then
  xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --output-on-failure -j2
else
  ctest --output-on-failure -j2
fi
cd "$ROOT"
bash scripts/fuzz.sh --seconds "${FUZZ_SECONDS:-20}"
