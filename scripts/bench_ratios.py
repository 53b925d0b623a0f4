#!/usr/bin/env python3
"""Prints Armature/ozz and Armature/ACL ratios from the benchmarks' JSON output (make bench).

Pairs are BM_VsOzz_<what>_Armature against BM_VsOzz_<what>_Ozz (and
BM_VsOzz_<what>_OzzIframes), and BM_VsAcl_<what>_Armature against
BM_VsAcl_<what>_Acl (armature-bench-acl). A ratio is Armature's CPU time over
the other library's: above 1 Armature is slower. With
--benchmark_repetitions=N the ratio is taken per repetition (Armature's i-th
run over the other's i-th run) and min and median are printed. Pairs with a
skipped half are listed as skipped. BM_VsAcl_Size/<clip> runs print as a
table: each clip's bytes per joint-sample, errors (cm) and compression times
for both, then ACL at the largest precision whose worst error on our
metric is within the bound (acl_fair_*). Several JSON files may be given (armature-bench's, armature-bench-acl's).
"""
import json
import re
import statistics
import sys

LIBRARIES = [("BM_VsOzz_", "Ozz", "ozz-animation 0.16"), ("BM_VsAcl_", "Acl", "ACL 2.1")]
UNITS = {"ns": 1, "us": 1e3, "ms": 1e6, "s": 1e9}


def print_pairs(runs, prefix, variant, title):
    times, skipped = {}, {}
    for r in runs:
        name = r.get("run_name", r["name"])
        if not name.startswith(prefix) or r.get("run_type", "iteration") != "iteration":
            continue
        if r.get("error_occurred") or r.get("skipped"):
            skipped[name] = r.get("error_message", "skipped")
            continue
        times.setdefault(name, []).append(r["cpu_time"] * UNITS[r["time_unit"]])
    pairs = []
    for name in sorted(set(times) | set(skipped)):
        m = re.fullmatch(r"%s(.+)_(%s\w*)" % (prefix, variant), name)
        if m:
            pairs.append((m.group(1), "%s%s_Armature" % (prefix, m.group(1)), name, m.group(2)))
    if not pairs:
        return
    print("\nArmature / %s (CPU time; > 1: Armature slower)" % title)
    for what, ours, theirs, label_variant in pairs:
        label = "%s vs %s" % (what, label_variant)
        if ours in skipped or theirs in skipped or ours not in times or theirs not in times:
            why = skipped.get(theirs) or skipped.get(ours) or "not run"
            print("  %-36s skipped: %s" % (label, why))
            continue
        ratios = [a / b for a, b in zip(times[ours], times[theirs])]
        a, b = statistics.median(times[ours]), statistics.median(times[theirs])
        print("  %-36s %6.2fx  (min %.2fx, median %.2fx over %d run%s; %.1f vs %.1f ns)" %
              (label, a / b, min(ratios), statistics.median(ratios), len(ratios), "" if len(ratios) == 1 else "s", a, b))


def print_sizes(runs):
    rows = [r for r in runs if r.get("run_name", r["name"]).startswith("BM_VsAcl_Size/") and "armature_bpjs" in r]
    if not rows:
        return
    print("\nCompressed clips, Armature / ACL 2.1 at the same bound (bytes per joint-sample; errors in cm)")
    print("  %-58s %6s %6s %7s %7s %6s %9s %9s %9s %9s %8s %8s" %
          ("clip", "joints", "frames", "ours", "ACL", "ratio", "p99", "worst", "ACL p99", "ACL worst", "ours ms", "ACL ms"))
    for r in rows:
        clip = re.sub(r"/iterations:\d+$", "", r.get("run_name", r["name"])[len("BM_VsAcl_Size/"):])
        print("  %-58s %6d %6d %7.3f %7.3f %5.2fx %9.5f %9.5f %9.5f %9.5f %8.1f %8.1f" %
              (clip[-58:], r["joints"], r["frames"], r["armature_bpjs"], r["acl_bpjs"],
               r["armature_bpjs"] / r["acl_bpjs"] if r["acl_bpjs"] else float("nan"), r["armature_p99_cm"],
               r["armature_worst_cm"], r["acl_p99_cm"], r["acl_worst_cm"], r["armature_ms"], r["acl_ms"]))
    fair = [r for r in rows if "acl_fair_bpjs" in r]
    if not fair:
        return
    print("\nACL 2.1 at the largest precision whose worst error on our metric is within the bound")
    print("  %-58s %7s %7s %6s %9s %9s %10s %8s %8s %6s" %
          ("clip", "ours", "ACL", "ratio", "ACL p99", "ACL worst", "ACL prec", "ours ms", "ACL ms", "scale"))
    for r in fair:
        clip = re.sub(r"/iterations:\d+$", "", r.get("run_name", r["name"])[len("BM_VsAcl_Size/"):])
        print("  %-58s %7.3f %7.3f %5.2fx %9.5f %9.5f %10.6f %8.1f %8.1f %6.1f" %
              (clip[-58:], r["armature_bpjs"], r["acl_fair_bpjs"],
               r["armature_bpjs"] / r["acl_fair_bpjs"] if r["acl_fair_bpjs"] else float("nan"), r["acl_fair_p99_cm"],
               r["acl_fair_worst_cm"], r["acl_fair_precision_cm"], r["armature_ms"], r["acl_fair_ms"],
               r["rest_world_scale"]) + ("" if r.get("acl_fair_met", 1) else "  (bound not met)"))


def main(paths):
    runs = []
    for path in paths:
        with open(path) as f:
            runs += json.load(f).get("benchmarks", [])
    for prefix, variant, title in LIBRARIES:
        print_pairs(runs, prefix, variant, title)
    print_sizes(runs)


if __name__ == "__main__":
    main(sys.argv[1:])
