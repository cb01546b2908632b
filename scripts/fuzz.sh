#!/usr/bin/env bash
# Runs the libFuzzer targets (build-asan/tests/fuzz, from
# scripts/test_sanitize.sh) on seed corpora built from data/ and the hostile
# inputs (tests/hostile/make_inputs.py).
#
#   scripts/fuzz.sh [--seconds N] [READER...]
#
# N seconds per reader (default 3600, the one-hour run); readers: rig camera
# voxels pose_csv timestamps matroska (default all). A finding (crash, hang
# over 10 s, leak, out-of-memory over 2 GB) stops that reader with exit 1
# and leaves the input in build-asan/fuzz/<reader>/crash-*; the corpus grows
# in build-asan/fuzz/<reader>/corpus.
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD
seconds=3600
if [[ ${1:-} == --seconds ]]; then
  seconds=$2
  shift 2
fi
readers=("$@")
((${#readers[@]})) || readers=(rig camera voxels pose_csv timestamps matroska)
BIN=$ROOT/build-asan/tests/fuzz
WORK=$ROOT/build-asan/fuzz
source scripts/sanitizer/env.sh

# Seeds: the shipped files, a short synthetic recording, the hostile inputs
# (those under 64 KB: libFuzzer mutates small inputs best).
seeds=$WORK/seeds
if [[ ! -d $seeds ]]; then
  mkdir -p "$seeds"/{rig,camera,voxels,pose_csv,timestamps,matroska}
  rec=$WORK/rec
  ripple=$ROOT/build-asan/app/ripple
  [[ -x $ripple ]] || ripple=$ROOT/build/app/ripple
  "$ripple" synth --out "$rec" --frames 4 --size 64x48 \
    --video "$rec/v.mkv" >/dev/null 2>&1
  python3 "$ROOT/tests/hostile/make_inputs.py" "$ROOT" "$rec" "$WORK/hostile"
  cp "$ROOT"/data/rig/*.yml "$rec/rig.yml" "$seeds/rig/"
  cp "$ROOT"/data/camera/*.yml "$rec/camera.yml" "$seeds/camera/"
  find "$WORK/hostile/rig" -name '*.yml' -size -64k -exec cp {} "$seeds/rig/" \;
  find "$WORK/hostile/cam" -name '*.yml' -size -64k -exec cp {} "$seeds/camera/" \;
  find "$WORK/hostile/rig" -name '*.vox' -size -64k -exec cp {} "$seeds/voxels/" \;
  printf 'ripple-voxels 1\n2 2 2\n# z layer 0\n01\n10\n# z layer 1\n11\n00\n' \
    >"$seeds/voxels/small.vox"
  head -c 60000 "$rec/groundtruth.csv" >"$seeds/pose_csv/groundtruth.csv"
  for d in "$WORK"/hostile/ts_*; do
    cp "$d/timestamps.csv" "$seeds/timestamps/$(basename "$d").csv"
  done
  printf 'frame,time_s\n0,0\n1,0.033\n2,0.067\n' >"$seeds/timestamps/good.csv"
  cp "$rec/v.mkv" "$seeds/matroska/"
  for f in "$WORK"/hostile/vid/*.mkv; do head -c 65536 "$f" >"$seeds/matroska/$(basename "$f")"; done
fi

status=0
for r in "${readers[@]}"; do
  [[ -x $BIN/fuzz_$r ]] || { echo "fuzz: build first (scripts/test_sanitize.sh)" >&2; exit 2; }
  mkdir -p "$WORK/$r/corpus"
  echo "fuzz: $r for $seconds s"
  if ! (cd "$WORK/$r" && "$BIN/fuzz_$r" -max_total_time="$seconds" \
      -timeout=10 -rss_limit_mb=2048 -max_len=65536 -print_final_stats=1 \
      corpus "$seeds/$r" 2>fuzz.log); then
    echo "fuzz: $r found a problem (build-asan/fuzz/$r/fuzz.log):" >&2
    grep -E 'ERROR|SUMMARY|runtime error|Test unit written' "$WORK/$r/fuzz.log" | head -5 >&2
    status=1
  fi
  grep -E '^stat::number_of_executed_units|^Done' "$WORK/$r/fuzz.log" | tr '\n' ' '
  echo
done
exit $status
