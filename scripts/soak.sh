#!/usr/bin/env bash
# Soak: `ripple replay` of a long synthetic video, sampling the process's
# resident memory and open descriptors once a second.
#
#   scripts/soak.sh [RIPPLE_BINARY] [FRAMES]
#
# Defaults: build-asan/app/ripple (the sanitizer build, leaks fatal) and
# 10000 frames of 160x120. Prints the samples and the growth of RSS from
# the end of warm-up (the first 10 % of the run) to the end; exit 1 when it
# exceeds 5 % or descriptors grow.
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=$(realpath "${1:-build-asan/app/ripple}")
FRAMES=${2:-10000}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/ripple_soak.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
if [[ $BIN == *build-asan* ]]; then
  export ASAN_OPTIONS=detect_leaks=1:abort_on_error=1
  export LSAN_OPTIONS=suppressions=$PWD/scripts/sanitizer/lsan.supp:print_suppressions=0
  export UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1
fi
"$BIN" synth --out "$WORK/rec" --frames "$FRAMES" --segment 1000 --size 160x120 \
  --preset clean --no-png --video "$WORK/rec/v.mkv" >/dev/null 2>&1
"$BIN" replay --input "$WORK/rec/v.mkv" --camera "$WORK/rec/camera.yml" \
  --rig "$WORK/rec/rig.yml" --headless --out "$WORK/out.mp4" \
  >"$WORK/replay.log" 2>&1 &
pid=$!
samples=()
while kill -0 "$pid" 2>/dev/null; do
  rss=$(awk '/VmRSS/ {print $2}' "/proc/$pid/status" 2>/dev/null || true)
  fds=$(ls "/proc/$pid/fd" 2>/dev/null | wc -l)
  [[ -n $rss ]] && samples+=("$rss $fds")
  sleep 1
done
wait "$pid" && rc=0 || rc=$?
printf '%s\n' "${samples[@]}" >"$WORK/samples.txt"
python3 - "$WORK/samples.txt" "$rc" <<'PY'
import sys
rows = [tuple(map(int, l.split())) for l in open(sys.argv[1]) if l.strip()]
rc = int(sys.argv[2])
if len(rows) < 10:
    print("soak: run too short to judge (%d samples), exit %d" % (len(rows), rc))
    sys.exit(1)
warm = rows[len(rows) // 10]
end = max(r[0] for r in rows[len(rows) // 10:])
growth = (end - warm[0]) / warm[0] * 100
fd_growth = rows[-1][1] - warm[1]
print("soak: %d samples, exit %d; RSS after warm-up %.1f MB, peak after "
      "%.1f MB (%+.1f %%); descriptors %d -> %d" %
      (len(rows), rc, warm[0] / 1024, end / 1024, growth, warm[1], rows[-1][1]))
sys.exit(0 if rc == 0 and growth < 5 and fd_growth <= 0 else 1)
PY
