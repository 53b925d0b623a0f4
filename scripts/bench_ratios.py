#!/usr/bin/env python3
"""Prints Armature/ozz ratios from armature-bench's JSON output (make bench).

Pairs are BM_VsOzz_<what>_Armature against BM_VsOzz_<what>_Ozz (and
BM_VsOzz_<what>_OzzIframes). A ratio is Armature's CPU time over ozz's: above
1 Armature is slower. With --benchmark_repetitions=N the ratio is taken per
repetition (Armature's i-th run over ozz's i-th run) and min and median are
printed. Pairs with a skipped half are listed as skipped.
"""
import json
import re
import statistics
import sys


def main(path):
    with open(path) as f:
        runs = json.load(f).get("benchmarks", [])
    times, skipped = {}, {}
    for r in runs:
        name = r.get("run_name", r["name"])
        if not name.startswith("BM_VsOzz_") or r.get("run_type", "iteration") != "iteration":
            continue
        if r.get("error_occurred") or r.get("skipped"):
            skipped[name] = r.get("error_message", "skipped")
            continue
        times.setdefault(name, []).append(r["cpu_time"] * {"ns": 1, "us": 1e3, "ms": 1e6, "s": 1e9}[r["time_unit"]])
    pairs = []
    for name in sorted(set(times) | set(skipped)):
        m = re.fullmatch(r"BM_VsOzz_(.+)_(Ozz\w*)", name)
        if m:
            pairs.append((m.group(1), "BM_VsOzz_%s_Armature" % m.group(1), name, m.group(2)))
    if not pairs:
        return
    print("\nArmature / ozz-animation 0.16 (CPU time; > 1: Armature slower)")
    for what, ours, theirs, variant in pairs:
        label = "%s vs %s" % (what, variant)
        if ours in skipped or theirs in skipped or ours not in times or theirs not in times:
            why = skipped.get(theirs) or skipped.get(ours) or "not run"
            print("  %-36s skipped: %s" % (label, why))
            continue
        ratios = [a / b for a, b in zip(times[ours], times[theirs])]
        a, b = statistics.median(times[ours]), statistics.median(times[theirs])
        print("  %-36s %6.2fx  (min %.2fx, median %.2fx over %d run%s; %.1f vs %.1f ns)" %
              (label, a / b, min(ratios), statistics.median(ratios), len(ratios), "" if len(ratios) == 1 else "s", a, b))


if __name__ == "__main__":
    main(sys.argv[1])
