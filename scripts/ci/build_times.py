#!/usr/bin/env python3
"""Sums a scripts/ci/time_launcher.sh log: total compile and link seconds,
seconds per target folder, and the slowest steps.

    python3 scripts/ci/build_times.py LOG [N]
"""
import collections
import re
import sys

rows = []
for line in open(sys.argv[1]):
    parts = line.split(maxsplit=1)
    if len(parts) == 2:
        rows.append((float(parts[0]), parts[1].strip()))
top = int(sys.argv[2]) if len(sys.argv) > 2 else 15


def kind(path):
    return "compile" if path.endswith(".o") else "link"


totals = collections.Counter()
counts = collections.Counter()
by_target = collections.Counter()
for secs, path in rows:
    totals[kind(path)] += secs
    counts[kind(path)] += 1
    m = re.search(r"CMakeFiles/([^/]+)\.dir/", path)
    name = m.group(1) if m else path.rsplit("/", 1)[-1]
    if name.startswith(("app_", "bench_", "calib_", "geometry_", "render_",
                        "sim_", "synth_", "tracking_")) or "_test" in path:
        name = "tests (compile + link)"
    elif name.startswith("fuzz_"):
        name = "fuzzers"
    by_target[name] += secs
for k in ("compile", "link"):
    print("%-8s %4d steps %7.1f s" % (k, counts[k], totals[k]))
print("per target (CPU-seconds, two jobs run at once):")
for name, secs in by_target.most_common():
    print("  %7.1f s  %s" % (secs, name))
print("slowest %d steps:" % top)
for secs, path in sorted(rows, reverse=True)[:top]:
    print("  %6.1f s  %s" % (secs, path))
