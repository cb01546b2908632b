#!/usr/bin/env bash
# Soak: `ripple replay` of a long synthetic video. Samples the process's
# resident memory (RSS), its live heap and the allocator's heap from inside
# it (scripts/soak/heap_sample.c, preloaded) and its open descriptors from
# outside, once a second, and counts the GL object names it holds
# (scripts/soak/gl_count.c, preloaded).
#
#   scripts/soak.sh [RIPPLE_BINARY] [FRAMES]
#
# Defaults: build-asan/app/ripple (the sanitizer build, leaks fatal) and
# 10000 frames of 320x240 of the demo's scene (`synth --preset demo`: fixed
# camera at 0.36 m, the pen dipping and stirring), where the tank is tracked
# in every frame, so that every frame runs the whole pipeline (tracking,
# clean plate, water, render, light estimate, encoder). SOAK_SIZE=WxH and
# SOAK_PRESET=NAME choose another input: at 160x120 with `--preset clean`
# (the former default) the tank's tags are too small to find in most
# segments and about 98 % of the frames only pass through.
#
# Prints the growth of RSS and of the live heap from the end of warm-up
# (the first 25 % of the samples) to their peak after it, the descriptors
# then and at the end, and the GL names' peak (when last reached) and
# count at exit; exit 1 when RSS or the live heap grows 5 % or more,
# descriptors grow, the GL peak is reached after warm-up or names are left
# at exit.
#
# Under the sanitizer build two ASan options are set for the soak
# (SOAK_ASAN_OPTIONS replaces them): both concern memory that ASan keeps
# for its reports, which RSS would count as the program's.
#   quarantine_size_mb=0: the quarantine holds back the last 256 MB of
#     freed blocks, so blocks of sizes not freed recently come from fresh
#     pages; RSS then follows the mix of block sizes (the former input rose
#     by 11 % near its end, the live heap by 0.3 MB).
#   malloc_context_size=0: ASan stores each distinct allocation stack once;
#     the fast unwinder, walking libraries built without frame pointers,
#     keeps finding new ones (23,000 a minute here), and RSS grew by about
#     1 MB a minute outside the heap.
# The live heap is judged as well, and the leak checker, bounds checks and
# UBSan stay on; a report comes without allocation stacks (rerun with
# SOAK_ASAN_OPTIONS=quarantine_size_mb=0). Measurements:
# docs/reliability.md, "Soak".
#
# SOAK_INPUT=DIR replays a recording made before (DIR/v.mkv, camera.yml,
# rig.yml) instead of synthesising one; SOAK_SYNTH=BINARY is the ripple that
# synthesises it otherwise (default build/app/ripple). SOAK_SAMPLES=FILE
# keeps the samples ("seconds rss_kB descriptors") and FILE.heap the heap
# samples ("seconds rss_kB live_bytes heap_bytes").
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=$(realpath "${1:-build-asan/app/ripple}")
FRAMES=${2:-10000}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/ripple_soak.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
ROOT=$PWD
if [[ $BIN == *build-asan* ]]; then
  source scripts/sanitizer/env.sh
  soak_asan=${SOAK_ASAN_OPTIONS:-quarantine_size_mb=0:malloc_context_size=0}
  ASAN_OPTIONS=$ASAN_OPTIONS:$soak_asan
fi
# The input comes from the release build where there is one (synthesising
# 10,000 frames under the sanitizers takes far longer than replaying them).
SYNTH=${SOAK_SYNTH:-build/app/ripple}
[[ -x $SYNTH ]] || SYNTH=$BIN
REC=$WORK/rec
if [[ -n ${SOAK_INPUT:-} ]]; then
  REC=$(realpath "$SOAK_INPUT")  # a recording synthesised before
else
  "$SYNTH" synth --out "$REC" --frames "$FRAMES" --segment 1000 \
    --size "${SOAK_SIZE:-320x240}" --preset "${SOAK_PRESET:-demo}" --no-png \
    --video "$REC/v.mkv" >/dev/null 2>&1
fi
cc -O1 -shared -fPIC -o "$WORK/gl_count.so" scripts/soak/gl_count.c -ldl
cc -O1 -shared -fPIC -o "$WORK/heap_sample.so" scripts/soak/heap_sample.c \
  -lpthread
RIPPLE_GL_COUNT_FILE=$WORK/gl.txt RIPPLE_HEAP_SAMPLE_FILE=$WORK/heap.txt \
  LD_PRELOAD="$WORK/gl_count.so $WORK/heap_sample.so" \
  "$BIN" replay --input "$REC/v.mkv" --camera "$REC/camera.yml" \
  --rig "$REC/rig.yml" --headless --out "$WORK/out.mp4" \
  >"$WORK/replay.log" 2>&1 &
pid=$!
samples=()
SECONDS=0
while kill -0 "$pid" 2>/dev/null; do
  rss=$(awk '/VmRSS/ {print $2}' "/proc/$pid/status" 2>/dev/null || true)
  fds=$(ls "/proc/$pid/fd" 2>/dev/null | wc -l)
  [[ -n $rss ]] && samples+=("$SECONDS $rss $fds")
  sleep 1
done
wait "$pid" && rc=0 || rc=$?
printf '%s\n' "${samples[@]}" >"$WORK/samples.txt"
if [[ -n ${SOAK_SAMPLES:-} ]]; then
  cp "$WORK/samples.txt" "$SOAK_SAMPLES"
  cp "$WORK/heap.txt" "$SOAK_SAMPLES.heap"
fi
[[ -n ${ASAN_OPTIONS:-} ]] && echo "soak: ASAN_OPTIONS=$ASAN_OPTIONS"
grep -a -o 'tank tracked in [0-9]*/[0-9]* frames' "$WORK/replay.log" |
  sed 's/^/soak: /' || true
((rc == 0)) || tail -20 "$WORK/replay.log"
python3 - "$WORK/samples.txt" "$rc" "$WORK/gl.txt" "$WORK/heap.txt" <<'PY'
import sys
rows = [tuple(map(int, l.split())) for l in open(sys.argv[1]) if l.strip()]
rc = int(sys.argv[2])
gl = [l.split() for l in open(sys.argv[3]) if l.strip()]
# The heap samples' last lines may come from the exit (destructors, the
# leak check): kept, they only lower the live heap and can raise RSS.
heap = [tuple(map(float, l.split())) for l in open(sys.argv[4])
        if len(l.split()) == 4]
if len(rows) < 10 or len(heap) < 10 or not gl:
    print("soak: run too short to judge (%d samples), exit %d" % (len(rows), rc))
    sys.exit(1)
MB = 1024.0 * 1024.0
w = len(heap) // 4
warm = heap[w]
rss_peak = max(h[1] for h in heap[w:])
live_peak = max(h[2] for h in heap[w:])
rss_growth = (rss_peak - warm[1]) / warm[1] * 100
live_growth = (live_peak - warm[2]) / warm[2] * 100
# Descriptors: the outside sample nearest the end of warm-up, and the last.
fd_warm = min(rows, key=lambda r: abs(r[0] - warm[0]))[2]
fd_growth = rows[-1][2] - fd_warm
for i in range(0, len(heap), max(1, len(heap) // 10)):
    h = heap[i]
    print("soak: t=%5.1f s  RSS %7.1f MB  live heap %6.1f MB  allocator heap "
          "%6.1f MB" % (h[0], h[1] / 1024, h[2] / MB, h[3] / MB))
print("soak: %d samples, exit %d; after warm-up (t=%.1f s): RSS %.1f MB, "
      "peak after %.1f MB (%+.1f %%); live heap %.1f MB, peak after %.1f MB "
      "(%+.1f %%); allocator heap %.1f -> %.1f MB; descriptors %d -> %d" %
      (len(heap), rc, warm[0], warm[1] / 1024, rss_peak / 1024, rss_growth,
       warm[2] / MB, live_peak / MB, live_growth, warm[3] / MB,
       max(h[3] for h in heap[w:]) / MB, fd_warm, rows[-1][2]))
peaks, final = gl[:-1], gl[-1]
last_peak_s = float(peaks[-1][0]) if peaks else 0.0
print("soak: GL names: peak %s live, last reached at %.1f s of %.1f s; at exit "
      "%s live (%s created, %s deleted)" %
      (peaks[-1][1] if peaks else 0, last_peak_s, heap[-1][0], final[1],
       final[2], final[3]))
gl_ok = int(final[1]) == 0 and last_peak_s <= warm[0]
ok = (rc == 0 and rss_growth < 5 and live_growth < 5 and fd_growth <= 0 and
      gl_ok)
sys.exit(0 if ok else 1)
PY
