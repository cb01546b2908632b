#!/usr/bin/env bash
# README command 2: set up, build, and run the whole test suite.
# GL tests use EGL surfaceless llvmpipe; the GLFW test runs under Xvfb.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
cd build
if command -v xvfb-run >/dev/null && [[ -z "${DISPLAY:-}" ]]; then
  # -noreset: by default Xvfb resets when its last client disconnects, and a
  # window test connecting during that reset fails to open the display.
  xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --output-on-failure -j2
else
  ctest --output-on-failure -j2
fi
