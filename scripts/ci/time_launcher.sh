#!/usr/bin/env bash
# Compiler launcher that logs the wall seconds of each compile or link:
#   cmake -DCMAKE_CXX_COMPILER_LAUNCHER=scripts/ci/time_launcher.sh ...
# appends "<seconds> <output file>" to $RIPPLE_TIME_LOG (default
# /tmp/ripple_build_times.log). scripts/ci/build_times.py sums the log.
start=$(date +%s.%N)
"$@"
rc=$?
end=$(date +%s.%N)
out=?
prev=
for a in "$@"; do
  [[ $prev == -o ]] && out=$a
  prev=$a
done
echo "$(echo "$end - $start" | bc) $out" >>"${RIPPLE_TIME_LOG:-/tmp/ripple_build_times.log}"
exit $rc
