#!/usr/bin/env python3
"""scripts/bench_ratios.py on hand-made armature-bench JSON: per-repetition
ratios (min, median), the ratio of the medians, time units, aggregates
ignored, skipped halves reported with their message, other benchmarks ignored."""
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


def ratios(benchmarks):
    with tempfile.NamedTemporaryFile("w", suffix=".json", delete=False) as f:
        json.dump({"context": {}, "benchmarks": benchmarks}, f)
    try:
        out = subprocess.run([sys.executable, SCRIPT, f.name], check=True, capture_output=True, text=True).stdout
    finally:
        os.unlink(f.name)
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


if __name__ == "__main__":
    unittest.main()
