"""Joint world positions printed by `armature pose --motion` against three.js's
own AnimationMixer (tests/reference/motion_reference.mjs, node) on
RobotExpressive: two override layers with PHASE and with NONE sync, three
layers of total weight below 1, additive layers (reference at 0 and inside
the clip), an upper-body mask. Every joint must agree within 1e-4 of the
model's size (the extent of its joints at rest), the clips imported with
`--clip-error exact`. The one-clip case is run again on a copy imported at the
server's default bound, 0.01 cm on points 3 cm from each joint (0.0001 in
RobotExpressive's metres): its clips report a worst error within the bound and
its joints agree within the tolerance + the bound.

usage: motion_vs_threejs.py SERVER_BIN CLI_BIN SHARED_DATA_DIR
"""
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from server_fixture import Server  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
RELATIVE_TOLERANCE = 1e-4
ASSET = "robot"
DEFAULT_ASSET = "robot_default"
DEFAULT_BOUND = 0.0001  # the default --clip-error, 0.01 cm, in glTF's metres
ONE_CLIP = "one clip"

# Motions with the glTF animation names; the server's clips are "robot.<name>".
CASES = {
    ONE_CLIP: {
        "motion": {"layers": [{"clip": "Walking"}]},
        "times": [0.1, 0.55, 0.97],
    },
    "two overrides, PHASE": {
        "motion": {"layers": [{"clip": "Walking", "weight": 0.6}, {"clip": "Running", "weight": 0.4}],
                   "sync": "PHASE"},
        "times": [0.0, 0.37, 1.3, 2.71],
    },
    "two overrides, NONE, speed and offset": {
        "motion": {"layers": [{"clip": "Walking", "weight": 0.7},
                              {"clip": "Running", "weight": 0.5, "speed": 1.3, "timeOffset": 0.2}],
                   "sync": "NONE"},
        "times": [0.05, 0.62, 1.9],
    },
    "three layers, total weight 0.75": {
        "motion": {"layers": [{"clip": "Idle", "weight": 0.3}, {"clip": "Walking", "weight": 0.25},
                              {"clip": "Wave", "weight": 0.2}]},
        "times": [0.2, 1.1, 2.4],
    },
    "additive nod on a walk": {
        "motion": {"layers": [{"clip": "Walking"},
                              {"clip": "Yes", "mode": "ADDITIVE", "weight": 0.8},
                              {"clip": "No", "mode": "ADDITIVE", "weight": 0.5, "referenceTime": 0.5}]},
        "times": [0.3, 0.9, 1.45],
    },
    "upper-body mask": {
        "motion": {"layers": [{"clip": "Walking"}, {"clip": "Wave", "mask": ["Abdomen"]}]},
        "times": [0.15, 0.8, 1.6],
    },
    "masked wave at half weight over a run": {
        "motion": {"layers": [{"clip": "Running"}, {"clip": "Wave", "weight": 0.5, "mask": ["ShoulderR"]},
                              {"clip": "Idle", "weight": 0.25}]},
        "times": [0.4, 1.2],
    },
}


def server_motion(motion, asset=ASSET):
    m = json.loads(json.dumps(motion))
    for layer in m["layers"]:
        layer["clip"] = f"{asset}.{layer['clip']}"
    return m


def cli_pose(cli, target, motion_file, t):
    r = subprocess.run([cli, "--server", target, "pose", "--motion", motion_file, "--time", repr(t), "--json"],
                       capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"armature pose --motion failed: {r.stderr}")
    return {j["name"]: j["translation"] for j in json.loads(r.stdout)["joints"]}


def extent(positions):
    lo = [min(p[i] for p in positions) for i in range(3)]
    hi = [max(p[i] for p in positions) for i in range(3)]
    return math.dist(lo, hi)


def main():
    server_bin, cli, data = sys.argv[1:4]
    glb = os.path.join(data, "gltf", "RobotExpressive", "RobotExpressive.glb")
    if not os.path.exists(glb):
        print(f"SKIP: {glb} is not present (../shared/data is only beside the project's own clone)")
        return 0
    node = shutil.which("node")
    if node is None or not os.path.isdir(os.path.join(HERE, "node_modules", "three")):
        print("FAIL: node or tests/reference/node_modules/three is missing: run scripts/setup.sh test")
        return 1
    work = tempfile.mkdtemp(prefix="armature-motion-")
    cases_file = os.path.join(work, "cases.json")
    with open(cases_file, "w") as f:
        json.dump(list(CASES.values()), f)
    reference = json.loads(subprocess.run([node, os.path.join(HERE, "motion_reference.mjs"), glb, cases_file],
                                          check=True, capture_output=True, text=True, cwd=HERE).stdout)
    failures, compared = 0, 0
    with Server(server_bin, ["--no-demo"]) as server:
        for asset, precision in ((ASSET, ["--clip-error", "exact"]), (DEFAULT_ASSET, [])):
            r = subprocess.run([cli, "--server", server.target, "import", glb, "--name", asset, *precision],
                               capture_output=True, text=True)
            if r.returncode != 0:
                raise RuntimeError(f"import {glb} failed: {r.stderr}")
            for clip in json.loads(r.stdout)["clips"]:
                if asset == ASSET and not clip["exact"]:
                    print(f"FAIL {clip['name']}: imported exact but is not")
                    failures += 1
                if asset == DEFAULT_ASSET and (clip["exact"] or clip["worstErrorCm"] > clip["errorBoundCm"]):
                    print(f"FAIL {clip['name']}: worst {clip['worstErrorCm']} cm over its bound "
                          f"{clip['errorBoundCm']} cm (exact: {clip['exact']})")
                    failures += 1
        # The model's size: its joints' extent at rest (Idle's weight 0 leaves the rest pose).
        rest_file = os.path.join(work, "rest.json")
        with open(rest_file, "w") as f:
            json.dump(server_motion({"layers": [{"clip": "Idle", "weight": 0}]}), f)
        size = extent(list(cli_pose(cli, server.target, rest_file, 0.0).values()))
        tolerance = RELATIVE_TOLERANCE * size
        print(f"model size {size:.4f}, tolerance {tolerance:.2e}")
        runs = [(name, case, frames, ASSET, tolerance) for (name, case), frames in zip(CASES.items(), reference)]
        runs.append((ONE_CLIP + ", default bound", CASES[ONE_CLIP], reference[0], DEFAULT_ASSET,
                     tolerance + DEFAULT_BOUND))
        for name, case, frames, asset, tolerance in runs:
            motion_file = os.path.join(work, f"case{compared}.json")
            with open(motion_file, "w") as f:
                json.dump(server_motion(case["motion"], asset), f)
            worst = 0.0
            for t, want in zip(case["times"], frames):
                got = cli_pose(cli, server.target, motion_file, t)
                common = [j for j in got if j in want]
                if len(common) < 40:
                    print(f"FAIL {name} t={t}: only {len(common)} joints in common with three.js")
                    failures += 1
                for j in common:
                    d = math.dist(got[j], want[j])
                    worst = max(worst, d)
                    if d > tolerance:
                        failures += 1
                        if failures <= 20:
                            print(f"FAIL {name} t={t} joint {j}: armature {got[j]} three.js {want[j]} (off {d:.3e})")
            compared += 1
            print(f"{name}: largest difference {worst:.3e} ({worst / size:.2e} of the size)")
    if failures:
        print(f"{failures} joint positions differ from three.js")
        return 1
    print(f"OK: {compared} motions agree with three.js's AnimationMixer")
    return 0


if __name__ == "__main__":
    sys.exit(main())
