#!/usr/bin/env bash
# Installs every build and test dependency of Ripple from Debian 12 packages.
# Idempotent: packages already present are skipped, so a second run is quick.
set -euo pipefail

PACKAGES=(
  build-essential cmake pkg-config clang-format
  libopencv-core-dev libopencv-imgproc-dev libopencv-calib3d-dev
  libopencv-imgcodecs-dev libopencv-videoio-dev libopencv-highgui-dev
  libapriltag-dev libceres-dev libeigen3-dev libglm-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libglfw3-dev libegl-dev libgl-dev libosmesa6-dev libgles-dev
  libegl-mesa0 libgl1-mesa-dri mesa-utils
  libcairo2-dev libfftw3-dev xvfb xauth
  libyaml-dev libavutil-dev clang lld
)

missing=()
for p in "${PACKAGES[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "ok installed"; then
    missing+=("$p")
  fi
done

if ((${#missing[@]} == 0)); then
  echo "setup: all ${#PACKAGES[@]} packages present"
  exit 0
fi

SUDO=""
if [[ $(id -u) -ne 0 ]]; then SUDO="sudo"; fi
echo "setup: installing ${missing[*]}"
export DEBIAN_FRONTEND=noninteractive
$SUDO apt-get update -qq
$SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
