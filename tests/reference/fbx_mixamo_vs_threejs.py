"""A Mixamo-style FBX through a real server (issue 33): tests/data/fbx/
mixamo_walk.fbx (mixamorig: names; tests/tools/make_mixamo_fbx.cc) is
imported with `armature import` (format detected from the file), its clip's
world pose equals three.js's FBXLoader playing the FBX itself
(fbx_reference.mjs), it is retargeted onto RobotExpressive and onto the demo
character, the retargeted clips are exported as .glb with the characters'
meshes, and three.js's GLTFLoader plays each glb with every joint where
`armature pose --space world` puts it, within 1e-4 of the model's size. The
import's warnings report the FBX units. After a restart on the same data
dir the FBX asset is still there. Skipped without ../shared/data.

usage: fbx_mixamo_vs_threejs.py SERVER_BIN CLI_BIN SHARED_DATA_DIR
"""
import json
import math
import os
import shutil
import sys
import tempfile

sys.path.insert(0, os.path.dirname(__file__))
from export_vs_threejs import cli_pose, run  # noqa: E402
from motion_vs_threejs import extent  # noqa: E402
from server_fixture import Server  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
FBX = os.path.join(HERE, "..", "data", "fbx", "mixamo_walk.fbx")
RELATIVE_TOLERANCE = 1e-4
CLIP = "mixamo.walk"


def compare(label, want_by_time, got_by_time, times):
    """Counts joints farther apart than the tolerance; prints the largest gap."""
    size = extent(list(got_by_time[0].values()))
    tolerance = RELATIVE_TOLERANCE * size
    failures, worst, compared = 0, 0.0, 0
    for t, want, got in zip(times, want_by_time, got_by_time):
        for joint, p in got.items():
            if joint not in want or any(v is None for v in want[joint]):
                continue  # three.js has no such node, or NaN (the EndSite leaves, see fbx_reference_test.cc)
            d = math.dist(p, want[joint])
            worst, compared = max(worst, d), compared + 1
            if d > tolerance:
                failures += 1
                if failures <= 10:
                    print(f"FAIL {label} t={t} joint {joint}: armature {p} three.js {want[joint]} (off {d:.3e})")
    if compared == 0:
        print(f"FAIL {label}: no joint compared")
        failures += 1
    print(f"{label}: {compared} joint positions, largest difference {worst:.3e} = {worst / size:.2e} of size {size:.3f}")
    return failures


def main():
    server_bin, cli, data = sys.argv[1:4]
    robot = os.path.join(data, "gltf", "RobotExpressive", "RobotExpressive.glb")
    if not os.path.exists(robot):
        print(f"SKIP: {robot} is not present (../shared/data is only beside the project's own clone)")
        return 0
    node = shutil.which("node")
    if node is None or not os.path.isdir(os.path.join(HERE, "node_modules", "three")):
        print("FAIL: node or tests/reference/node_modules/three is missing: run scripts/setup.sh test")
        return 1
    work = tempfile.mkdtemp(prefix="armature-fbx-")
    data_dir = os.path.join(work, "data")
    failures = 0
    times = [0.0, 0.05, 0.13, 0.2]
    with Server(server_bin, data_dir=data_dir) as server:
        target = server.target
        imported = json.loads(run([cli, "--server", target, "--json", "import", FBX, "--name", "mixamo"]))
        warnings = " ".join(imported.get("warnings", []))
        if "FBX units" not in warnings:
            print(f"FAIL: the import does not report the FBX units: {imported}")
            failures += 1
        run([cli, "--server", target, "import", robot, "--name", "robot"])
        # The FBX's own clip against three.js's FBXLoader on the same file.
        reference = json.loads(run([node, os.path.join(HERE, "fbx_reference.mjs"), FBX, "0",
                                    ",".join(map(repr, times))]))
        want = [{name: frames[i] for name, frames in reference["nodes"].items()} for i in range(len(times))]
        failures += compare("mixamo_walk.fbx", want, [cli_pose(cli, target, CLIP, t) for t in times], times)
        for character in ("robot", "demo_character"):
            clip = f"walk_on_{character}"
            mapped = json.loads(run([cli, "--server", target, "--json", "retarget", CLIP, "--to", character,
                                     "--name", clip]))["mapping"]
            # The mixamorig: names read as body parts: hips, spine, head, both arms and legs at least.
            if len(mapped) < 12:
                print(f"FAIL {clip}: only {len(mapped)} joints mapped: {mapped}")
                failures += 1
            out = os.path.join(work, clip + ".glb")
            run([cli, "--server", target, "export", clip, "-o", out, "--with-meshes"])
            times_file = out + ".times.json"
            with open(times_file, "w") as f:
                json.dump(times, f)
            played = json.loads(run([node, os.path.join(HERE, "export_reference.mjs"), out, times_file]))
            if not played["meshes"]:
                print(f"FAIL {clip}: three.js found no skinned mesh in the glb")
                failures += 1
            failures += compare(clip + ".glb", played["frames"], [cli_pose(cli, target, clip, t) for t in times],
                                times)
    with Server(server_bin, data_dir=data_dir) as server:
        listed = json.loads(run([cli, "--server", server.target, "--json", "list"]))["assets"]
        if not any(a["name"] == "mixamo" and a.get("format") == "fbx" for a in listed):
            print(f"FAIL: after a restart the FBX asset is missing: {[(a['name'], a.get('format')) for a in listed]}")
            failures += 1
    shutil.rmtree(work, ignore_errors=True)
    if failures:
        print(f"{failures} failures")
        return 1
    print("OK: the Mixamo FBX imports, plays as three.js plays it, retargets, exports and reloads")
    return 0


if __name__ == "__main__":
    sys.exit(main())
