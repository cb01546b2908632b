#!/usr/bin/env bash
# The sanitizer run: builds Ripple with clang, AddressSanitizer and UBSan
# (-fno-sanitize-recover: any report fails) and the libFuzzer targets into
# build-asan/, runs the whole test suite under it, then each fuzzer for a
# bounded time (FUZZ_SECONDS, default 20) on its seed corpus.
#
#   scripts/test_sanitize.sh [--ci] [cmake configure arguments...]
#
# --ci (what .ci/run calls): the part that fits CI's time on a 2-core
# machine: `ripple`, the file readers' and writers' tests and the fuzzers
# only, then the hostile-input suite and those tests under the sanitizers
# and each fuzzer for FUZZ_SECONDS (default 10). The whole suite under the
# sanitizers takes over 20 minutes here (docs/reliability.md, "Sanitizer
# run in CI").
# Leak reports inside Mesa, fontconfig and libusb are suppressed
# (scripts/sanitizer/lsan.supp); any other leak fails.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
ci=false
if [[ ${1:-} == --ci ]]; then
  ci=true
  shift
fi
# The tests --ci runs: every reader and writer of files (rig and camera
# YAML, poses CSV, voxels, image sizes, videos) and the hostile inputs.
ci_tests=(tracking_yaml_tree_test tracking_files_test tracking_pose_csv_test
          sim_obstacle_test app_wxh_test app_video_out_test)
ci_regex='^(hostile/inputs|tracking/(yaml_tree|files|pose_csv)_test|sim/obstacle_test|app/(wxh|video_out)_test)$'
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
ctest_args=(--output-on-failure -j2)
if $ci; then
  cmake --build build-asan -j"${RIPPLE_JOBS:-2}" --target ripple \
    "${ci_tests[@]}" fuzz_rig fuzz_camera fuzz_voxels fuzz_pose_csv \
    fuzz_timestamps fuzz_matroska
  ctest_args+=(-R "$ci_regex")
else
  cmake --build build-asan -j"${RIPPLE_JOBS:-2}"
fi
source scripts/sanitizer/env.sh
cd build-asan
if command -v xvfb-run >/dev/null && [[ -z "${DISPLAY:-}" ]]; then
  xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest "${ctest_args[@]}"
else
  ctest "${ctest_args[@]}"
fi
cd "$ROOT"
if $ci; then
  bash scripts/fuzz.sh --seconds "${FUZZ_SECONDS:-10}"
else
  bash scripts/fuzz.sh --seconds "${FUZZ_SECONDS:-20}"
fi
