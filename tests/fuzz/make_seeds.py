#!/usr/bin/env python3
"""Writes small seed inputs for a fuzz target's format into a directory:
hand-made files covering each format's features, plus copies of small real
files from ../shared/data when it is present (never committed).
    make_seeds.py <bvh|gltf|obj|detect|other> <out dir> [shared data dir]"""
import base64
import json
import os
import shutil
import struct
import sys

BVH = """HIERARCHY
ROOT Hips
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Chest
  {
    OFFSET 0 5 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    JOINT Neck
    {
      OFFSET 0 2 0
      End Site
      {
        OFFSET 0 3 0
      }
    }
  }
}
MOTION
Frames: 3
Frame Time: 0.0333333
0 1 2 3 4 5 6 7 8
1 2 3 4 5 6 7 8 9
-1.5 +2 3e1 40 50 60 -70 80 90
"""

OBJ = """# a quad and a triangle
o thing
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 0
v 0 0 1
vt 0 0
vn 0 0 1
f 1/1/1 2/1/1 3/1/1 4/1/1
f -1 1 2
g rest
s off
usemtl none
f 1//1 3//1 \\
  5//1
"""


def gltf_model():
    """A skinned triangle on a two-joint chain, a morph target and a two-key
    animation of every path; returns (json dict, bin bytes)."""
    b = bytearray()
    views, accessors = [], []

    def add(fmt, values, type_, component=5126, count=None, **extra):
        while len(b) % 4:
            b.append(0)
        offset = len(b)
        b.extend(struct.pack("<%d%s" % (len(values), fmt), *values))
        views.append({"buffer": 0, "byteOffset": offset, "byteLength": len(b) - offset})
        width = {"SCALAR": 1, "VEC3": 3, "VEC4": 4, "MAT4": 16}[type_]
        a = {"bufferView": len(views) - 1, "componentType": component,
             "count": count if count is not None else len(values) // width, "type": type_}
        a.update(extra)
        accessors.append(a)
        return len(accessors) - 1

    pos = add("f", [0, 0, 0, 1, 0, 0, 0, 1, 0], "VEC3", min=[0, 0, 0], max=[1, 1, 0])
    nrm = add("f", [0, 0, 1] * 3, "VEC3")
    idx = add("H", [0, 1, 2], "SCALAR", component=5123)
    joints = add("B", [0, 1, 0, 0] * 3, "VEC4", component=5121)
    weights = add("f", [0.5, 0.5, 0, 0] * 3, "VEC4")
    ibm = add("f", [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1] * 2, "MAT4")
    delta = add("f", [0, 0, 1] * 3, "VEC3")
    times = add("f", [0, 1], "SCALAR", min=[0], max=[1])
    trans = add("f", [0, 0, 0, 1, 0, 0], "VEC3")
    rot = add("f", [0, 0, 0, 1, 0, 0.7071, 0, 0.7071], "VEC4")
    cubic = add("f", [0] * 18, "VEC3")
    wts = add("f", [0, 1], "SCALAR")
    sparse_idx = add("B", [1, 0, 0, 0], "SCALAR", component=5121)
    doc = {
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 2]}],
        "nodes": [
            {"name": "root", "children": [1], "translation": [0, 1, 0]},
            {"name": "tip", "rotation": [0, 0, 0, 1], "scale": [1, 1, 1]},
            {"name": "skinned", "mesh": 0, "skin": 0, "weights": [0.25]},
            {"name": "matrix", "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 2, 0, 0, 1]},
        ],
        "skins": [{"joints": [0, 1], "inverseBindMatrices": ibm, "skeleton": 0}],
        "meshes": [{"name": "tri", "weights": [0],
                    "extras": {"targetNames": ["up"]},
                    "primitives": [{"attributes": {"POSITION": pos, "NORMAL": nrm, "JOINTS_0": joints,
                                                   "WEIGHTS_0": weights},
                                    "indices": idx, "mode": 4,
                                    "targets": [{"POSITION": delta}]}]}],
        "animations": [{"name": "move", "samplers": [
            {"input": times, "output": trans, "interpolation": "LINEAR"},
            {"input": times, "output": rot, "interpolation": "STEP"},
            {"input": times, "output": cubic, "interpolation": "CUBICSPLINE"},
            {"input": times, "output": wts}],
            "channels": [
                {"sampler": 0, "target": {"node": 0, "path": "translation"}},
                {"sampler": 1, "target": {"node": 1, "path": "rotation"}},
                {"sampler": 2, "target": {"node": 1, "path": "scale"}},
                {"sampler": 3, "target": {"node": 2, "path": "weights"}}]}],
        "bufferViews": views,
        "accessors": accessors,
    }
    # A sparse accessor: the normals with element 1 replaced.
    accessors.append({"bufferView": nrm, "componentType": 5126, "count": 3, "type": "VEC3",
                      "sparse": {"count": 1, "indices": {"bufferView": sparse_idx, "componentType": 5121},
                                 "values": {"bufferView": delta}}})
    return doc, bytes(b)


def gltf_text(doc, data):
    d = dict(doc)
    d["buffers"] = [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(data).decode()}]
    return json.dumps(d, separators=(",", ":")).encode()


def glb(doc, data):
    d = dict(doc)
    d["buffers"] = [{"byteLength": len(data)}]
    text = json.dumps(d, separators=(",", ":")).encode()
    text += b" " * (-len(text) % 4)
    data += b"\0" * (-len(data) % 4)
    return (b"glTF" + struct.pack("<II", 2, 28 + len(text) + len(data)) + struct.pack("<I", len(text)) +
            b"JSON" + text + struct.pack("<I", len(data)) + b"BIN\0" + data)


def write(out, name, data):
    with open(os.path.join(out, name), "wb") as f:
        f.write(data)


def main():
    kind, out = sys.argv[1], sys.argv[2]
    shared = sys.argv[3] if len(sys.argv) > 3 else ""
    os.makedirs(out, exist_ok=True)
    doc, data = gltf_model()
    seeds = {
        "bvh": {"small.bvh": BVH.encode(), "crlf.bvh": BVH.replace("\n", "\r\n").encode()},
        "gltf": {"skinned.gltf": gltf_text(doc, data), "skinned.glb": glb(doc, data)},
        "obj": {"quad.obj": OBJ.encode()},
    }
    seeds["detect"] = {
        "bvh": b"/walk.bvh\n" + BVH.encode(),
        "gltf": b"gltf/\n" + gltf_text(doc, data),
        "glb": b"/x.bin\n" + glb(doc, data),
        "obj": b"/\n" + OBJ.encode(),
    }
    for name, blob in seeds.get(kind, {}).items():
        write(out, name, blob)
    # Small real files, when the shared data is beside the clone.
    exts = {"bvh": (".bvh",), "gltf": (".gltf", ".glb"), "obj": (".obj",)}.get(kind, ())
    if shared and os.path.isdir(shared):
        for root, _, files in os.walk(shared):
            for f in files:
                path = os.path.join(root, f)
                if f.endswith(exts) and os.path.getsize(path) <= 64 * 1024:
                    shutil.copyfile(path, os.path.join(out, "shared_" + f))


if __name__ == "__main__":
    main()
