"""glTF files written by `armature export` against three.js in node
(tests/reference/export_reference.mjs): a BVH clip (CMU 01_01), a glTF clip
with its meshes (RobotExpressive's Walking and Dance) and CMU 01_01 retargeted
onto RobotExpressive (`armature retarget`) with the robot's meshes are exported as .glb (and
one as .gltf), loaded by GLTFLoader and played by AnimationMixer; every
joint's world position at several times must equal `armature --json pose CLIP
--time T --space world` of the original clip within 1e-4 of the model's size
(the extent of its joints at t=0). With CLIP_ERROR `exact` the server keeps
every clip exact and export writes the stored keys; with `default` it keeps
them at its default bound (0.01 cm on points 3 cm from each joint) and export
writes the runtime form's samples at each clip's frames, which `pose` gives
there too (between frames both interpolate them). Skipped without
../shared/data.

usage: export_vs_threejs.py SERVER_BIN CLI_BIN SHARED_DATA_DIR [exact|default]
"""
import json
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from motion_vs_threejs import extent  # noqa: E402
from server_fixture import Server  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
RELATIVE_TOLERANCE = 1e-4

# (clip, output file, extra export flags, times[, the skeleton whose meshes come along])
CASES = [
    ("cmu_on_robot", "retargeted.glb", ["--with-meshes"], [0.0, 2.5, 9.81, 17.3], "robot"),
    ("cmu", "cmu.glb", [], [0.0, 1.0 / 240, 3.3, 11.27, 22.9]),
    ("cmu", "cmu.gltf", [], [0.5, 7.77]),
    ("robot.Walking", "walking.glb", ["--with-meshes"], [0.0, 0.13, 0.51, 0.97]),
    ("robot.Dance", "dance.glb", ["--with-meshes"], [0.07, 0.9, 1.61]),
    ("demo_character.walk", "demo.glb", ["--with-meshes"], [0.1, 1.45, 2.2]),
    # A clip made by CreateClip (CUBIC without tangents: stored as CUBICSPLINE with the tangents the
    # server computed), between and at its keys.
    ("made", "made.glb", [], [0.0, 0.13, 0.4, 0.55, 0.9, 1.2]),
]

# CreateClip keys on the demo walk's skeleton (centimetres): CUBIC swings, a LINEAR and a STEP track.
MADE_KEYS = {"tracks": [
    {"joint": "Hips", "times": [0, 0.4, 0.9, 1.2], "interpolation": "CUBIC",
     "translations": [0, 90, 0, 10, 95, 20, -5, 85, 35, 0, 90, 50],
     "euler": [0, 0, 0, 20, 35, -10, -15, -30, 5, 0, 10, 0], "eulerOrder": "ZXY"},
    {"joint": "LeftKnee", "times": [0, 0.3, 0.6, 1.2], "interpolation": "CUBIC",
     "euler": [10, 0, 0, 80, 0, 0, 5, 10, 0, 60, -10, 0]},
    {"joint": "Spine", "times": [0, 1.2], "interpolation": "LINEAR", "euler": [0, 0, 0, 0, 90, 0]},
    {"joint": "RightKnee", "times": [0, 0.5], "interpolation": "STEP", "euler": [0, 0, 0, 45, 0, 0]},
]}


def three_name(name):
    """The node name three.js's GLTFLoader gives (PropertyBinding.sanitizeNodeName)."""
    return re.sub(r"[\[\]\.:/]", "", re.sub(r"\s", "_", name))


def run(args):
    r = subprocess.run(args, capture_output=True, text=True)
    if r.returncode != 0:
        raise RuntimeError(f"{' '.join(args)} failed: {r.stderr}")
    return r.stdout


def character_meshes(cli, target, clip, skeleton=None):
    """(meshes, vertices, morph targets) the server holds skinned to the clip's skeleton (or `skeleton`)."""
    assets = json.loads(run([cli, "--server", target, "--json", "list"]))["assets"]
    skeleton = skeleton or next(c["skeleton"] for a in assets for c in a["clips"] if c["name"] == clip)
    meshes = [m for a in assets for m in a["meshes"] if m.get("skeleton") == skeleton]
    return len(meshes), sum(m["vertexCount"] for m in meshes), sum(len(m.get("targetNames", [])) for m in meshes)


def cli_pose(cli, target, clip, t):
    out = run([cli, "--server", target, "--json", "pose", clip, "--time", repr(t), "--space", "world"])
    return {three_name(j["name"]): j["translation"] for j in json.loads(out)["joints"]}


def main():
    server_bin, cli, data = sys.argv[1:4]
    clip_error = sys.argv[4] if len(sys.argv) > 4 else "exact"
    bvh = os.path.join(data, "bvh", "cmu_01_01.bvh")
    glb = os.path.join(data, "gltf", "RobotExpressive", "RobotExpressive.glb")
    for path in (bvh, glb):
        if not os.path.exists(path):
            print(f"SKIP: {path} is not present (../shared/data is only beside the project's own clone)")
            return 0
    node = shutil.which("node")
    if node is None or not os.path.isdir(os.path.join(HERE, "node_modules", "three")):
        print("FAIL: node or tests/reference/node_modules/three is missing: run scripts/setup.sh test")
        return 1
    work = tempfile.mkdtemp(prefix="armature-export-")
    failures = 0
    with Server(server_bin, [] if clip_error == "default" else ["--clip-error", clip_error]) as server:
        run([cli, "--server", server.target, "import", bvh, "--name", "cmu"])
        run([cli, "--server", server.target, "import", glb, "--name", "robot"])
        keys = os.path.join(work, "made.json")
        with open(keys, "w") as f:
            json.dump(MADE_KEYS, f)
        run([cli, "--server", server.target, "create-clip", "--skeleton", "demo_walk", "--keys", keys, "--name", "made"])
        run([cli, "--server", server.target, "retarget", "cmu", "--to", "robot"])
        for clip, filename, flags, times, *meshes_of in CASES:
            out = os.path.join(work, filename)
            run([cli, "--server", server.target, "export", clip, "-o", out, *flags])
            times_file = os.path.join(work, filename + ".times.json")
            with open(times_file, "w") as f:
                json.dump(times, f)
            reference = json.loads(run([node, os.path.join(HERE, "export_reference.mjs"), out, times_file]))
            # With --with-meshes, three.js finds every mesh of the character, skinned, with its morph targets.
            want = character_meshes(cli, server.target, clip, *meshes_of) if flags else (0, 0, 0)
            found = reference["meshes"]
            got = (len(found), sum(m["vertices"] for m in found), sum(m["morphTargets"] for m in found))
            if got != want:
                print(f"FAIL {filename}: three.js found (meshes, vertices, morph targets) {got}, expected {want}")
                failures += 1
            size = extent(list(cli_pose(cli, server.target, clip, 0.0).values()))
            tolerance = RELATIVE_TOLERANCE * size
            worst, compared = 0.0, 0
            for t, want in zip(times, reference["frames"]):
                got = cli_pose(cli, server.target, clip, t)
                missing = [j for j in got if j not in want]
                if missing:
                    print(f"FAIL {filename} t={t}: joints missing in three.js: {missing[:5]}")
                    failures += 1
                for j in got:
                    if j not in want:
                        continue
                    d = math.dist(got[j], want[j])
                    worst = max(worst, d)
                    compared += 1
                    if d > tolerance:
                        failures += 1
                        if failures <= 20:
                            print(f"FAIL {filename} t={t} joint {j}: armature {got[j]} three.js {want[j]} "
                                  f"(off {d:.3e})")
            print(f"{filename} ({clip}, {os.path.getsize(out)} bytes, {len(reference['meshes'])} meshes): "
                  f"{compared} joint positions, largest difference {worst:.3e} = {worst / size:.2e} of the "
                  f"size {size:.3f} (tolerance {tolerance:.2e})")
    shutil.rmtree(work, ignore_errors=True)
    if failures:
        print(f"{failures} joint positions differ from three.js")
        return 1
    print(f"OK: {len(CASES)} exported files play in three.js as armature poses them")
    return 0


if __name__ == "__main__":
    sys.exit(main())
