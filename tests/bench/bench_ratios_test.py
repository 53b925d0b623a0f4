#!/usr/bin/env python3
"""scripts/bench_ratios.py on hand-made armature-bench JSON: per-repetition
ratios (min, median), the ratio of the medians, time units, aggregates
ignored, skipped halves reported with their message, other benchmarks ignored;
ACL pairs and the compressed clips' size table from a second file."""
import json
import os
import subprocess
import sys
import tempfile
import unittest

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "bench_ratios.py")


def run(name, cpu, unit="ns", rep=0, run_type="iteration"):
    return {"name": name if run_type == "iteration" else name + "_median", "run_name": name, "run_type": run_type,
            "repetition_index": rep, "cpu_time": cpu, "real_time": cpu * 3, "time_unit": unit}


def script_output(*files):
    names = []
    for benchmarks in files:
        with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
            json.dump({"context": {}, "benchmarks": benchmarks}, f)
        names.append(f.name)
    try:
        return subprocess.run([sys.executable, SCRIPT] + names, check=True, capture_output=True, text=True).stdout
    finally:
        for name in names:
            os.unlink(name)


def ratios(benchmarks, *more):
    out = script_output(benchmarks, *more)
    return {line.split()[0] + " " + line.split()[2]: line.strip() for line in out.splitlines() if " vs " in line}


class BenchRatios(unittest.TestCase):
    def test_per_repetition_min_and_median(self):
        # Armature 300, 310, 290 ns against ozz 100, 100, 50 ns: per run 3.0, 3.1, 5.8
        # (min 3.00, median 3.10); medians 300 / 100 = 3.00.
        out = ratios([run("BM_VsOzz_A_Armature", t, rep=i) for i, t in enumerate((300, 310, 290))] +
                     [run("BM_VsOzz_A_Ozz", t, rep=i) for i, t in enumerate((100, 100, 50))] +
                     [run("BM_VsOzz_A_Armature", 300, run_type="aggregate"), run("BM_VsOzz_A_Ozz", 1, run_type="aggregate")])
        self.assertIn("3.00x  (min 3.00x, median 3.10x over 3 runs; 300.0 vs 100.0 ns)", out["A Ozz"])

    def test_units_and_variants(self):
        # 2 us against 4000 ns is 0.5; the OzzIframes variant pairs with the same Armature run.
        out = ratios([run("BM_VsOzz_B_Armature", 2, unit="us"), run("BM_VsOzz_B_Ozz", 4000),
                      run("BM_VsOzz_B_OzzIframes", 1, unit="us"), run("BM_Other", 1)])
        self.assertIn("0.50x", out["B Ozz"])
        self.assertIn("2.00x", out["B OzzIframes"])
        self.assertEqual(len(out), 2)

    def test_skipped_half(self):
        skipped = run("BM_VsOzz_C_Ozz", 0)
        skipped.update(error_occurred=True, error_message="ozz-animation not built: tarball absent")
        out = ratios([run("BM_VsOzz_C_Armature", 5), skipped])
        self.assertIn("skipped: ozz-animation not built: tarball absent", out["C Ozz"])

    def test_acl_pairs_and_sizes_from_a_second_file(self):
        # ozz in one file, ACL in another: both pairs print; the size row gives the ratio of bytes.
        size = run("BM_VsAcl_Size/bvh/cmu_01_01.bvh/iterations:1", 1)
        size.update(joints=31, frames=2752, armature_bpjs=2.2, acl_bpjs=2.45, armature_p99_cm=0.008,
                    armature_worst_cm=0.00999, acl_p99_cm=0.0101, acl_worst_cm=0.0178, armature_ms=90, acl_ms=150)
        ozz = [run("BM_VsOzz_A_Armature", 80), run("BM_VsOzz_A_Ozz", 100)]
        acl = [run("BM_VsAcl_Decompress_Armature", 450), run("BM_VsAcl_Decompress_Acl", 500), size]
        out = ratios(ozz, acl)
        self.assertIn("0.80x", out["A Ozz"])
        self.assertIn("0.90x", out["Decompress Acl"])
        table = script_output(ozz, acl)
        self.assertIn("Armature / ACL 2.1", table)
        row = [line for line in table.splitlines() if "cmu_01_01.bvh" in line][0]
        self.assertIn("0.90x", row)
        self.assertIn("2.200   2.450", row)


if __name__ == "__main__":
    unittest.main()
