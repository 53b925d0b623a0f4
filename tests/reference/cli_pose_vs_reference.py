"""World positions printed by `armature pose` against an independent forward
kinematics (SciPy, tests/reference/bvh_fk.py), at frame times and between
frames, for the CMU capture and for copies of it re-expressed in other channel
orders with a non-zero root offset (tests/reference/bvh_reorder.py). These
are imported with `--clip-error exact` (the stored keys), within TOLERANCE.
The CMU capture is imported once more at the server's default bound, 0.01 cm
on points 3 cm from each joint (CMU's units count as centimetres): there the
server reports a worst error within the bound, and the positions agree within
TOLERANCE + the bound.

usage: cli_pose_vs_reference.py SERVER_BIN CLI_BIN SHARED_DATA_DIR
"""
import json
import os
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from server_fixture import Server  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
TOLERANCE = 1e-3
DEFAULT_BOUND = 0.01  # the default --clip-error, 0.01 cm, in CMU's units (centimetres)
# Frame times (k/120) and times between frames.
TIMES = [0.0, 1 / 120, 100 / 120, 0.123, 5.0041, 11.11, 22.9]


def reference(path, times):
    out = subprocess.run([sys.executable, os.path.join(HERE, "bvh_fk.py"), path, *map(str, times)],
                         check=True, capture_output=True, text=True).stdout
    return json.loads(out)


def cli_pose(cli, target, clip, t):
    r = subprocess.run([cli, "--server", target, "pose", clip, "--time", repr(t), "--json"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"armature pose failed: {r.stderr}")
    return json.loads(r.stdout)


def main():
    server_bin, cli, data = sys.argv[1:4]
    cmu = os.path.join(data, "bvh", "cmu_01_01.bvh")
    if not os.path.exists(cmu):
        print(f"SKIP: {cmu} is not present (../shared/data is only beside the project's own clone)")
        return 0
    passes, failures = 0, 0
    work = tempfile.mkdtemp(prefix="armature-bvh-")
    variants = {"cmu": (cmu, None), "cmu_default": (cmu, "default")}
    for order, offset in (("XZY", "3.5,-2,7.25"), ("YXZ", "-10,4,1")):
        path = os.path.join(work, f"cmu_{order.lower()}.bvh")
        subprocess.run([sys.executable, os.path.join(HERE, "bvh_reorder.py"), cmu, path, "--order", order,
                        f"--root-offset={offset}"], check=True)
        variants[f"cmu_{order.lower()}"] = (path, order)

    original = reference(cmu, TIMES)
    with Server(server_bin, ["--no-demo"]) as server:
        for name, (path, order) in variants.items():
            default = order == "default"
            precision = [] if default else ["--clip-error", "exact"]
            r = subprocess.run([cli, "--server", server.target, "import", path, "--name", name, *precision],
                               capture_output=True, text=True)
            if r.returncode != 0:
                raise RuntimeError(f"import {path} failed: {r.stderr}")
            clip = json.loads(r.stdout)["clips"][0]
            tolerance = TOLERANCE + (DEFAULT_BOUND if default else 0)
            if default:
                ok = (not clip["exact"] and clip["errorBoundCm"] == DEFAULT_BOUND
                      and clip["worstErrorCm"] <= DEFAULT_BOUND and clip["bytesPerJointSample"] < 4)
                print(f"{'ok  ' if ok else 'FAIL'} {name}: bound {clip['errorBoundCm']} cm, worst "
                      f"{clip['worstErrorCm']:.2e} cm, {clip['bytesPerJointSample']:.2f} B/joint-sample")
                passes, failures = passes + ok, failures + (not ok)
            elif not clip["exact"]:
                raise RuntimeError(f"{name}: imported with --clip-error exact but not exact: {clip}")
            ref = reference(path, TIMES)
            for i, t in enumerate(TIMES):
                pose = cli_pose(cli, server.target, name, t)
                names = [j["name"] for j in pose["joints"]]
                assert names == ref["joints"], f"{name}: joint order differs"
                worst = max(max(abs(a - b) for a, b in zip(j["translation"], p))
                            for j, p in zip(pose["joints"], ref["positions"][i]))
                # The re-expressed copies carry the same motion as the original.
                same_motion = max(max(abs(a - b) for a, b in zip(p, q))
                                  for p, q in zip(ref["positions"][i], original["positions"][i]))
                ok = worst <= tolerance and same_motion <= TOLERANCE
                print(f"{'ok  ' if ok else 'FAIL'} {name} ({order or 'ZYX'}) t={t:.4f}: "
                      f"max |cli - scipy| = {worst:.2e}, |variant - original| = {same_motion:.2e}")
                passes, failures = passes + ok, failures + (not ok)
    print(f"{passes} passed, {failures} failed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
