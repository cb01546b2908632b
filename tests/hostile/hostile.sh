#!/usr/bin/env bash
# Hostile-input regression suite: crafted rig, camera, voxel, image,
# timestamps and video files (make_inputs.py) run through the `ripple`
# binary. Each case states the exit code and the message our one line must
# match; a crash (signal, sanitizer report), a hang (past the timeout), a
# success on a broken input, or a third-party line on stderr beside ours
# fails the case.
#
#   hostile.sh RIPPLE_BINARY SOURCE_DIR [--survey]
#
# --survey prints the table (inputs, clean, crashes, hangs, silent, noisy,
# other) instead of failing, to measure a build that predates the checks.
set -uo pipefail
BIN=$(realpath "$1")
SRC=$(realpath "$2")
SURVEY=${3:-}
TIMEOUT_S=${HOSTILE_TIMEOUT_S:-60}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/ripple_hostile.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
cd "$WORK"

# A short synthetic recording: PNG frames and a lossless MKV.
if ! "$BIN" synth --out rec --frames 12 --size 160x120 --video rec/v.mkv \
    >/dev/null 2>rec.log; then
  cat rec.log
  echo "hostile: cannot make the recording" >&2
  exit 1
fi
python3 "$SRC/tests/hostile/make_inputs.py" "$SRC" rec in || exit 1
IN=$WORK/in

n=0 clean=0 crashes=0 hangs=0 silent=0 noisy=0 other=0
failed=()

# check NAME EXPECT_RC REGEX CMD...: runs CMD with the time limit and sorts
# the outcome.
check() {
  local name=$1 want=$2 regex=$3
  shift 3
  local out=$WORK/out/$name
  rm -rf "$out"
  mkdir -p "$out"
  local args=()
  for a in "$@"; do args+=("${a//@OUT@/$out}"); done
  timeout -s KILL "$TIMEOUT_S" "$BIN" "${args[@]}" >"$out.stdout" 2>"$out.stderr"
  local rc=$?
  n=$((n + 1))
  local verdict
  # Our own lines: "ripple: ..." and the commands' progress ("track: ...").
  local foreign
  # (progress bars "[==>   ] 3/12 frames" too).
  foreign=$(tr '\r' '\n' <"$out.stderr" |
    grep -a -v -E '^((ripple|sim|synth|track|replay|markers|demo|calib)( |:)|\[[=> ])' |
    grep -v '^ *$' | head -3)
  local last
  last=$(grep -a -E '^ripple: ' "$out.stderr" | tail -1)
  if ((rc == 137)); then
    verdict=hang hangs=$((hangs + 1))
  elif ((rc >= 128)) || grep -q -E 'Sanitizer|runtime error:' "$out.stderr"; then
    verdict=crash crashes=$((crashes + 1))
  elif ((rc == 0 && want != 0)); then
    verdict=silent silent=$((silent + 1))
  elif [[ -n "$foreign" ]]; then
    verdict=noisy noisy=$((noisy + 1))
  elif ((rc == want)) && [[ "$last" =~ $regex ]] && ! grep -q 'unexpected error' "$out.stderr"; then
    verdict=clean clean=$((clean + 1))
  else
    verdict=other other=$((other + 1))
  fi
  printf '%-28s %-6s rc=%-3s %s\n' "$name" "$verdict" "$rc" \
    "$( (if [[ $verdict == noisy ]]; then echo "$foreign"; else echo "$last"; fi) | head -1 | cut -c1-150)"
  [[ $verdict == clean ]] || failed+=("$name")
}

R="$SRC/data/rig/default.yml"
C="$SRC/data/camera/default_640x480.yml"
sim() { check "$1" "$2" "$3" sim --rig "$4" --duration 0.05 --out @OUT@/h; }
synth() { check "$1" "$2" "$3" synth --camera "$4" --rig "$R" --frames 1 --out @OUT@; }
track() { check "$1" "$2" "$3" track --input "$4" --rig "${5:-$R}" --out @OUT@/p.csv; }
replay() { check "$1" "$2" "$3" replay --input "$4" --rig "${5:-$R}" --headless --out @OUT@/o.mp4; }

# Rig files: bounded before they are parsed, every parser failure one line.
sim rig_deep_map 2 "rig file .*deep_map.yml.*nest" "$IN/rig/deep_map.yml"
sim rig_deep_seq 2 "rig file .*deep_seq.yml.*nest" "$IN/rig/deep_seq.yml"
sim rig_deep_block 2 "rig file .*deep_block.yml.*nest" "$IN/rig/deep_block.yml"
sim rig_empty_key 2 "rig file .*empty_key.yml" "$IN/rig/empty_key.yml"
sim rig_empty 2 "rig file .*empty.yml" "$IN/rig/empty.yml"
sim rig_binary 2 "rig file .*binary.yml" "$IN/rig/binary.yml"
sim rig_nul 2 "rig file .*nul.yml" "$IN/rig/nul.yml"
sim rig_huge_file 2 "rig file .*huge_file.yml.*bytes" "$IN/rig/huge_file.yml"
sim rig_long_line 2 "rig file .*long_line.yml" "$IN/rig/long_line.yml"
sim rig_many_tags 2 "rig file .*many_tags.yml" "$IN/rig/many_tags.yml"
sim rig_alias_bomb 2 "rig file .*alias_bomb.yml.*alias" "$IN/rig/alias_bomb.yml"
sim rig_missing 2 "rig file .*no_such.yml.*cannot open" "$IN/rig/no_such.yml"
sim rig_is_dir 2 "rig file .*" "$IN/rig"
sim rig_cut 2 "rig file .*cut.yml" "$IN/rig/cut.yml"
sim rig_tab_indent 2 "rig file .*tab_indent.yml" "$IN/rig/tab_indent.yml"
sim rig_not_utf8 2 "rig file .*not_utf8.yml" "$IN/rig/not_utf8.yml"
sim rig_dup_key 2 "rig file .*dup_key.yml.*rig_version" "$IN/rig/dup_key.yml"
sim rig_string_version 2 "rig file .*rig_version" "$IN/rig/string_version.yml"
sim rig_inf_level 2 "rig file .*water_level" "$IN/rig/inf_level.yml"
sim rig_huge_inner 2 "rig file .*inner_size" "$IN/rig/huge_inner_size.yml"
sim rig_tiny_inner 2 "rig file .*inner_size" "$IN/rig/tiny_inner_size.yml"
sim rig_huge_edge 2 "rig file .*edge" "$IN/rig/huge_edge.yml"
check markers_id_beyond 2 "rig file .*beyond tag36h11" markers --rig "$IN/rig/board_id_beyond.yml" --out @OUT@
track track_board_id_beyond 2 "rig file .*beyond tag36h11" "$WORK/rec/frames" "$IN/rig/board_id_beyond.yml"
track track_pen_id_beyond 2 "rig file .*beyond tag36h11" "$WORK/rec/frames" "$IN/rig/pen_id_beyond.yml"
replay replay_huge_inner 2 "rig file .*inner_size" "$WORK/rec/v.mkv" "$IN/rig/huge_inner_size.yml"

# Voxel files: the header is checked before the body is read.
sim vox_garbage 2 "vox_garbage.vox.*voxel file" "$IN/rig/vox_garbage.yml"
sim vox_claims_huge 2 "vox_claims_huge.vox" "$IN/rig/vox_claims_huge.yml"
sim vox_cut 2 "vox_cut.vox.*voxels" "$IN/rig/vox_cut.yml"
sim vox_sparse_zero 2 "vox_sparse_zero.vox.*voxel file" "$IN/rig/vox_sparse_zero.yml"

# Camera files.
synth cam_huge 2 "camera file .*huge.yml.*exceeds" "$IN/cam/huge.yml"
synth cam_big 2 "camera file .*big.yml.*exceeds" "$IN/cam/big.yml"
synth cam_inf_width 2 "camera file .*image_width" "$IN/cam/inf_width.yml"
synth cam_nan_fx 2 "camera file .*nan_fx.yml" "$IN/cam/nan_fx.yml"
synth cam_matrix_huge 2 "camera file .*camera_matrix" "$IN/cam/matrix_claims_huge.yml"
synth cam_matrix_bad_dt 2 "camera file .*camera_matrix" "$IN/cam/matrix_bad_dt.yml"
synth cam_deep 2 "camera file .*deep.yml.*nest" "$IN/cam/deep.yml"
synth cam_empty 2 "camera file .*empty.yml" "$IN/cam/empty.yml"
synth cam_binary 2 "camera file .*binary.yml" "$IN/cam/binary.yml"
synth cam_dist_100 2 "camera file .*distortion" "$IN/cam/dist_100.yml"
synth cam_tiny 2 "camera file .*tiny.yml" "$IN/cam/tiny.yml"

# Image folders.
track img_1x1 2 "frames are 1x1 but camera file" "$IN/img_1x1"
track img_4x3 1 "cannot read image .*img_4x3/000.png.*read 0 of 1 frames" "$IN/img_4x3"
track img_huge_header 1 "img_huge_header/000.png.*16384" "$IN/img_huge_header"
track img_text 1 "cannot read image .*img_text/000.png" "$IN/img_text"
track img_zero 1 "cannot read image .*img_zero/000.png" "$IN/img_zero"
track img_cut 1 "img_cut/000.png" "$IN/img_cut"

# timestamps.csv of a raw recording.
track ts_extra 2 "timestamps.csv.* line 2" "$IN/ts_extra"
track ts_garbage 2 "timestamps.csv.* line 2" "$IN/ts_garbage"
track ts_short 2 "timestamps.csv.*1 rows for 3 images" "$IN/ts_short"
track ts_nan 2 "timestamps.csv.* line 3" "$IN/ts_nan"
track ts_huge_line 2 "timestamps.csv" "$IN/ts_huge_line"

# Videos.
replay vid_zero 2 "cannot open video .*zero.mp4" "$IN/vid/zero.mp4"
replay vid_text 2 "cannot open video .*text.mp4" "$IN/vid/text.mp4"
replay vid_header_only 1 "header_only.mkv.* truncated .*read 0 of 12 frames" "$IN/vid/header_only.mkv"
replay vid_cut95 1 "cut95.mkv.* read [0-9]+ of 12 frames" "$IN/vid/cut95.mkv"
replay vid_cut50 1 "cut50.mkv.* read [0-9]+ of 12 frames" "$IN/vid/cut50.mkv"
replay vid_corrupt_mid 1 "corrupt_mid.mkv.* [0-9]+ of 12 frames" "$IN/vid/corrupt_mid.mkv"
check track_vid_cut95 1 "cut95.mkv.* read [0-9]+ of 12 frames" track --input "$IN/vid/cut95.mkv" --out @OUT@/p.csv

echo "hostile: $n inputs, $clean clean, $crashes crashes, $hangs hangs," \
  "$silent silent, $noisy noisy, $other other"
if [[ $SURVEY != --survey ]] && ((${#failed[@]} > 0)); then
  echo "hostile: failed: ${failed[*]}" >&2
  exit 1
fi
exit 0
