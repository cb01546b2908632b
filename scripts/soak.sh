#!/usr/bin/env bash
# Soak: `ripple replay` of a long synthetic video, sampling the process's
# resident memory and open descriptors once a second, and counting the GL
# object names it holds (scripts/soak/gl_count.c, preloaded).
#
#   scripts/soak.sh [RIPPLE_BINARY] [FRAMES]
#
# Defaults: build-asan/app/ripple (the sanitizer build, leaks fatal) and
# 10000 frames of 160x120. Prints the growth of RSS from the end of warm-up
# (the first 25 % of the run: ASan's quarantine of freed blocks, 256 MB,
# fills over about the first fifth) to the end, the descriptors then and at the
# end, and the GL names' peak (when last reached) and count at exit; exit 1
# when RSS grows 5 % or more, descriptors grow, the GL peak is reached
# after warm-up or names are left at exit. SOAK_SAMPLES=FILE keeps the
# samples ("seconds rss_kB descriptors"); SOAK_SYNTH=BINARY the ripple that
# synthesises the input (default build/app/ripple).
set -euo pipefail
cd "$(dirname "$0")/.."
BIN=$(realpath "${1:-build-asan/app/ripple}")
FRAMES=${2:-10000}
WORK=$(mktemp -d "${TMPDIR:-/tmp}/ripple_soak.XXXXXX")
trap 'rm -rf "$WORK"' EXIT
ROOT=$PWD
if [[ $BIN == *build-asan* ]]; then
  source scripts/sanitizer/env.sh
fi
# The input comes from the release build where there is one (synthesising
# 10,000 frames under the sanitizers takes far longer than replaying them).
SYNTH=${SOAK_SYNTH:-build/app/ripple}
[[ -x $SYNTH ]] || SYNTH=$BIN
"$SYNTH" synth --out "$WORK/rec" --frames "$FRAMES" --segment 1000 --size 160x120 \
  --preset clean --no-png --video "$WORK/rec/v.mkv" >/dev/null 2>&1
cc -O1 -shared -fPIC -o "$WORK/gl_count.so" scripts/soak/gl_count.c -ldl
RIPPLE_GL_COUNT_FILE=$WORK/gl.txt LD_PRELOAD=$WORK/gl_count.so \
  "$BIN" replay --input "$WORK/rec/v.mkv" --camera "$WORK/rec/camera.yml" \
  --rig "$WORK/rec/rig.yml" --headless --out "$WORK/out.mp4" \
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
[[ -n ${SOAK_SAMPLES:-} ]] && cp "$WORK/samples.txt" "$SOAK_SAMPLES"
((rc == 0)) || tail -20 "$WORK/replay.log"
python3 - "$WORK/samples.txt" "$rc" "$WORK/gl.txt" <<'PY'
import sys
rows = [tuple(map(int, l.split())) for l in open(sys.argv[1]) if l.strip()]
rc = int(sys.argv[2])
gl = [l.split() for l in open(sys.argv[3]) if l.strip()]
if len(rows) < 10 or not gl:
    print("soak: run too short to judge (%d samples), exit %d" % (len(rows), rc))
    sys.exit(1)
w = len(rows) // 4
warm = rows[w]
end = max(r[1] for r in rows[w:])
growth = (end - warm[1]) / warm[1] * 100
fd_growth = rows[-1][2] - warm[2]
for i in range(0, len(rows), max(1, len(rows) // 10)):
    print("soak: t=%4d s  RSS %7.1f MB  descriptors %d" %
          (rows[i][0], rows[i][1] / 1024, rows[i][2]))
print("soak: %d samples, exit %d; RSS after warm-up (t=%d s) %.1f MB, peak "
      "after %.1f MB (%+.1f %%); descriptors %d -> %d" %
      (len(rows), rc, warm[0], warm[1] / 1024, end / 1024, growth, warm[2],
       rows[-1][2]))
peaks, final = gl[:-1], gl[-1]
last_peak_s = float(peaks[-1][0]) if peaks else 0.0
print("soak: GL names: peak %s live, last reached at %.1f s of %d s; at exit "
      "%s live (%s created, %s deleted)" %
      (peaks[-1][1] if peaks else 0, last_peak_s, rows[-1][0], final[1],
       final[2], final[3]))
gl_ok = int(final[1]) == 0 and last_peak_s <= warm[0]
sys.exit(0 if rc == 0 and growth < 5 and fd_growth <= 0 and gl_ok else 1)
PY
