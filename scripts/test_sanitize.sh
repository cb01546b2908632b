#!/usr/bin/env bash
# The sanitizer run of CI: builds Ripple with clang, AddressSanitizer and
# UBSan (-fno-sanitize-recover: any report fails) and the libFuzzer targets
# into build-asan/, runs the whole test suite under it, then each fuzzer for
# a bounded time (FUZZ_SECONDS, default 20) on its seed corpus.
# Leak reports inside Mesa, fontconfig and libusb are suppressed
# (scripts/sanitizer/lsan.supp); any other leak fails.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
launcher=()
if command -v ccache >/dev/null; then
  launcher=(-DCMAKE_C_COMPILER_LAUNCHER=ccache -DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
fi
# -O1: the sanitizers' usual level (fast enough to run the tests, quick to
# build); no benchmarks (not run by ctest).
cmake -S . -B build-asan -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ \
  -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O1 -g" -DCMAKE_C_FLAGS_RELWITHDEBINFO="-O1 -g" \
  -DRIPPLE_SANITIZE=ON -DRIPPLE_FUZZ=ON -DRIPPLE_BUILD_BENCHMARKS=OFF \
  "${launcher[@]}" >/dev/null
cmake --build build-asan -j"${RIPPLE_JOBS:-2}"
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1:detect_stack_use_after_return=0
export LSAN_OPTIONS=suppressions=$ROOT/scripts/sanitizer/lsan.supp:print_suppressions=0
export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
cd build-asan
if command -v xvfb-run >/dev/null && [[ -z "${DISPLAY:-}" ]]; then
  xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --output-on-failure -j2
else
  ctest --output-on-failure -j2
fi
cd "$ROOT"
bash scripts/fuzz.sh --seconds "${FUZZ_SECONDS:-20}"
