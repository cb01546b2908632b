#!/usr/bin/env bash
# README command 1: set up, build, and run the embedded default job.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/build.sh
./build/app/ripple demo --out out "$@"
