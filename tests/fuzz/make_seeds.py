#!/usr/bin/env python3
"""Writes small seed inputs for a fuzz target's format into a directory:
hand-made files covering each format's features, plus copies of small real
files from ../shared/data when it is present (never committed).
    make_seeds.py <bvh|gltf|obj|fbx|detect|transcode|path_template|import_upload|other> <out dir> [shared data dir]"""
import base64
import glob
import json
import os
import re
import shutil
import struct
import sys

PROTO_DIR = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "proto", "armature")

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

# A Mixamo-named node under a pivoted, pre-rotated parent, holding a triangle
# (the engine's FBX tests read it too).
with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "data", "fbx", "pivots.fbx")) as f:
    FBX = f.read()

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


def api_routes():
    """(method, template) of every google.api.http rule in the repo's protos."""
    routes = []
    for path in sorted(glob.glob(os.path.join(PROTO_DIR, "**", "*.proto"), recursive=True)):
        with open(path) as f:
            text = f.read()
        routes += [(m.upper(), t) for m, t in re.findall(r'\b(get|post|put|delete|patch): "([^"]+)"', text)]
    return routes


def concrete(template, value="walk"):
    """A request path for a template: each variable and wildcard becomes `value`."""
    return re.sub(r"\{[^}]*\}|\*\*|\*", value, template)


# REST requests for the transcoder: "<METHOD> <target>\n<content type>\n<body>".
TRANSCODE = {
    # binary REST: the body is the request's encoding (clip "x", then times [0.5] as a packed double)
    "evaluate_protobuf": "POST /v1/clips/walk:evaluate\napplication/x-protobuf\n"
                         "\n\x01x\x12\x08\x00\x00\x00\x00\x00\x00\x00\x00",
    "import_protobuf": "POST /v1/assets:import?filename=a.bvh\napplication/x-protobuf\n\x12\x03HIE",
    "evaluate": 'POST /v1/clips/walk:evaluate\napplication/json\n'
                '{"times":[0,0.5,1e3],"space":"SPACE_WORLD","interpolation":1,"joints":["Hips","Chest"]}',
    "stream_query": "GET /v1/clips/walk:stream?fps=30&speed=-1.5&loop=true&joints=Hips&joints=Chest"
                    "&space=SPACE_LOCAL&start_time=0.25\n\n",
    "fk": 'POST /v1/skeletons/arm:fk\napplication/json\n'
          '{"pose":{"rotations":[{"w":1,"x":0,"y":0,"z":0}]},"joints":["a"]}',
    "ik": 'POST /v1/skeletons/arm:solveIk\napplication/json\n'
          '{"solver":"DLS","effectors":[{"joint":"hand","position":{"x":1,"y":2,"z":3}}],'
          '"options":{"maxIterations":50},"free_joints":["elbow"],"maxChainDepth":2}',
    "ik_session": 'POST /v1/skeletons/arm:ikSession\napplication/x-ndjson\n'
                  '{"start":{"solver":"CCD"}}\n{"targets":[{"joint":"hand"}]}\n',
    "deform": 'POST /v1/meshes/m:deform\napplication/json\n'
              '{"weights":"COTANGENT","method":"ARAP","fixed":[0,1],"soft":true,"arapIterations":3}',
    "import_raw": "POST /v1/assets:import?filename=x.bvh&name=x&replace=true\napplication/octet-stream\n" + BVH,
    "import_json": 'POST /v1/assets:import?format=bvh\napplication/json\n"SElFUkFSQ0hZ"',
    "import_ndjson": 'POST /v1/assets:import\napplication/x-ndjson\n{"filename":"a.gltf","data":"e30="}\n'
                     '{"resource":"a.bin","data":"AAAA"}\n',
    "get_asset": "GET /v1/assets/a%20b\n\n",
    "delete_clip": "DELETE /v1/clips/walk?x=1\n\n",
    "skin_query": "POST /v1/meshes/m:skin\napplication/json\n"
                  '{"clip":"walk","time":0.5,"method":"DQS","morphWeights":[0.5,1]}',
    "blendshapes": 'POST /v1/meshes/m:blendshapes\ntext/plain\n{"weights":[1,2,3]}',
    "bind": 'POST /v1/meshes/m:bind\napplication/json\n{"skeleton":"s","method":"HEAT","maxInfluences":4}',
}


def path_template_seeds():
    """Each API template with paths that match it and some that nearly do."""
    seeds = {}
    for i, (_, t) in enumerate(api_routes()):
        paths = [concrete(t), concrete(t, "a%2Fb"), concrete(t, "x:y"), concrete(t).replace("/v1", "/v2"),
                 concrete(t) + "/extra?q=1#f"]
        seeds["api_%d" % i] = (t + "\n" + "\n".join(paths)).encode()
    seeds["nested"] = b"/v1/{name=assets/*/parts/**}:get\n/v1/assets/a/parts/b/c:get\n/v1/assets/a/parts:get"
    seeds["dotted"] = b"/v1/{start.skeleton}/{x=*}/lit/*:verb\n/v1/s/x/lit/y:verb\n/v1/s/x/lit/y"
    return seeds


def varint(n):
    out = bytearray()
    while True:
        b = n & 0x7F
        n >>= 7
        out.append(b | (0x80 if n else 0))
        if not n:
            return bytes(out)


def import_message(filename="", name="", fmt="", replace=False, data=b"", resource=""):
    """An ImportAssetRequest in the protobuf wire format, length-delimited."""
    m = bytearray()
    for field, value in ((1, filename), (2, name), (3, fmt)):
        if value:
            m += bytes([field << 3 | 2]) + varint(len(value.encode())) + value.encode()
    if replace:
        m += bytes([4 << 3, 1])
    if data:
        m += bytes([5 << 3 | 2]) + varint(len(data)) + data
    if resource:
        m += bytes([6 << 3 | 2]) + varint(len(resource.encode())) + resource.encode()
    return varint(len(m)) + bytes(m)


def import_upload_seeds():
    doc, data = gltf_model()
    external = dict(doc)
    external["buffers"] = [{"byteLength": len(data), "uri": "scene.bin"}]
    text = json.dumps(external, separators=(",", ":")).encode()
    bvh = BVH.encode()
    return {
        # first byte: the upload limit, 256 B << (byte % 8)
        "bvh_chunks": b"\x07" + import_message("walk.bvh", "walk", data=bvh[:100]) +
                      import_message(data=bvh[100:200]) + import_message(data=bvh[200:]),
        "gltf_resource": b"\x07" + import_message("scene.gltf", replace=True, data=text) +
                         import_message(resource="scene.bin", data=data),
        "obj_format": b"\x03" + import_message("m", fmt="obj", data=OBJ.encode()),
        "over_limit": b"\x00" + import_message("big.bvh", data=bvh),
        "late_header": b"\x07" + import_message("a.bvh", data=bvh[:50]) + import_message("b.bvh", data=bvh[50:]),
        "resource_twice": b"\x07" + import_message("a.gltf", data=text) + import_message(resource="r", data=b"1") +
                          import_message(resource="r", data=b"2"),
        "empty": b"\x01",
    }


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
        "fbx": {"pivots.fbx": FBX.encode()},
    }
    seeds["detect"] = {
        "bvh": b"/walk.bvh\n" + BVH.encode(),
        "gltf": b"gltf/\n" + gltf_text(doc, data),
        "glb": b"/x.bin\n" + glb(doc, data),
        "obj": b"/\n" + OBJ.encode(),
        "fbx": b"/x.fbx\n" + FBX.encode(),
    }
    seeds["transcode"] = {k: v.encode() for k, v in TRANSCODE.items()}
    for i, (method, template) in enumerate(api_routes()):  # every route, with an empty JSON body
        seeds["transcode"]["route_%d" % i] = ("%s %s\napplication/json\n{}" % (method, concrete(template))).encode()
    seeds["path_template"] = path_template_seeds()
    seeds["import_upload"] = import_upload_seeds()
    # first byte: the frame limit, 1 << (byte % 24); then a gRPC-Web body
    frame = lambda flag, m: bytes([flag]) + len(m).to_bytes(4, "big") + m
    seeds["grpc_web"] = {
        "one_frame": b"\x0a" + frame(0, b"\x0a\x09demo_walk"),
        "two_frames": b"\x0a" + frame(0, b"ab") + frame(0, b""),
        "trailer": b"\x0a" + frame(0x80, b"grpc-status: 0\r\ngrpc-message: \r\n"),
        "compressed": b"\x0a" + frame(1, b"x"),
        "over_limit": b"\x02" + frame(0, b"12345"),
        "cut_short": b"\x0a" + frame(0, b"abc")[:6],
        "base64": b"\x0a" + b"AAAAAAA=Zm9v",
    }
    # first byte: the message limit 1 << (byte % 20) and the split step; then client frames (masked)
    def ws(op, payload, fin=True, mask=b"\x01\x02\x03\x04"):
        n = len(payload)
        size = bytes([0x80 | n]) if n < 126 else bytes([0x80 | 126]) + n.to_bytes(2, "big")
        return bytes([(0x80 if fin else 0) | op]) + size + mask + bytes(c ^ mask[i % 4] for i, c in enumerate(payload))
    seeds["websocket"] = {
        "text": b"\x0a" + ws(1, b'{"targets": [{"effector": 0, "targetPosition": [1, 2, 3]}]}'),
        "fragments_and_ping": b"\x2d" + ws(2, b"ab", False) + ws(9, b"p") + ws(0, b"cd"),
        "close": b"\x05" + ws(8, b"\x03\xe8bye"),
        "medium": b"\x10" + ws(2, bytes(300)),
        "unmasked": b"\x0a" + b"\x81\x02{}",
        "over_limit": b"\x02" + ws(1, b"12345"),
    }
    for name, blob in seeds.get(kind, {}).items():
        write(out, name, blob)
    # Small real files, when the shared data is beside the clone.
    exts = {"bvh": (".bvh",), "gltf": (".gltf", ".glb"), "obj": (".obj",), "fbx": (".fbx",)}.get(kind, ())
    if shared and os.path.isdir(shared):
        for root, _, files in os.walk(shared):
            for f in files:
                path = os.path.join(root, f)
                if f.endswith(exts) and os.path.getsize(path) <= 64 * 1024:
                    shutil.copyfile(path, os.path.join(out, "shared_" + f))


if __name__ == "__main__":
    main()
