"""armature_client (clients/python) against a real armature-server.

References: the `armature` CLI's JSON (EvaluateClip, SkinMesh, EvaluateMotion
through the C++ client), a BVH written here with hand-derived poses, and the
server's own unary answers for its streams.

usage: test_client.py PYTHON SERVER_BIN CLI_BIN
PYTHON is the interpreter the package is installed in (python_client.install_offline's venv);
the test runs itself again in it.
"""
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import unittest
import urllib.request

from client_python import run_in_client_python  # noqa: E402

run_in_client_python()

import grpc
import numpy as np

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "reference"))
from server_fixture import Server  # noqa: E402

import armature_client  # noqa: E402
from armature_client import (AlreadyExists, ArmatureError, Client, InvalidArgument, NotFound,  # noqa: E402
                             Unauthenticated, DeadlineExceeded, Unavailable)

SERVER_BIN, CLI_BIN = sys.argv[2], sys.argv[3]
TOKEN = "py-client-token-7"
TIMES = [0.0, 0.25, 0.5, 1.1]

# Two joints, 2 frames at 0.5 s: the root translates, the child turns about Z.
HAND_BVH = """HIERARCHY
ROOT Base
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Arm
  {
    OFFSET 0 2 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 0 1 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.5
0 0 0 0 0 0 0 0 0
1 2 3 0 0 0 90 0 0
"""


class ClientTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server(SERVER_BIN)
        cls.client = Client(cls.server.target, timeout=30)

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.stop()

    def cli(self, *args):
        out = subprocess.run([CLI_BIN, "--server", self.server.target, "--json", *args], check=True,
                             stdout=subprocess.PIPE, text=True, timeout=60).stdout
        return json.loads(out)

    def assertClose(self, a, b, tol, what):
        err = float(np.max(np.abs(np.asarray(a, np.float64) - np.asarray(b, np.float64))))
        print(f"  {what}: max |difference| {err:.3g}")
        self.assertLessEqual(err, tol, what)

    def test_evaluate_clip_equals_the_cli(self):
        for space in ("world", "local"):
            p = self.client.evaluate_clip("demo_walk", TIMES, space=space)
            self.assertEqual(p.space, space)
            self.assertEqual(p.clip, "demo_walk")
            for i, t in enumerate(TIMES):
                ref = self.cli("pose", "demo_walk", "--time", repr(t), "--space", space)
                self.assertEqual(p.joint_names, [j["name"] for j in ref["joints"]])
                self.assertClose(p.translations[i], [j["translation"] for j in ref["joints"]], 1e-9,
                                 f"{space} translations at {t}")
                self.assertClose(p.rotations[i], [j["rotation"] for j in ref["joints"]], 1e-9,
                                 f"{space} rotations at {t}")

    def test_shapes_and_joint_subset(self):
        p = self.client.evaluate_clip("demo_walk", TIMES)
        n = len(self.client.get_skeleton(p.skeleton).joints)
        self.assertEqual(p.translations.shape, (len(TIMES), n, 3))
        self.assertEqual(p.rotations.shape, (len(TIMES), n, 4))
        self.assertEqual(p.scales.shape, (len(TIMES), n, 3))
        self.assertEqual(len(p.joint_names), n)
        np.testing.assert_array_equal(p.times, TIMES)
        self.assertClose(np.linalg.norm(p.rotations, axis=2), 1.0, 1e-6, "rotations are unit quaternions")
        pick = [p.joint_names[-1], p.joint_names[0]]
        sub = self.client.evaluate_clip("demo_walk", 0.5, joints=pick)
        self.assertEqual(sub.translations.shape, (1, 2, 3))
        self.assertEqual(sorted(sub.joint_names), sorted(pick))
        for k, name in enumerate(sub.joint_names):
            np.testing.assert_array_equal(sub.translations[0, k], p.translations[2, p.joint_names.index(name)])

    def test_imported_bvh_matches_hand_derived_poses(self):
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "hand.bvh")
            with open(path, "w") as f:
                f.write(HAND_BVH)
            # Exact: the poses below are checked to 1e-6, finer than the default bound.
            r = self.client.import_asset(path, name="py_hand", precision="exact")
            self.assertEqual(r.asset.name, "py_hand")
            self.assertTrue(r.asset.clips[0].exact)
            self.assertIn("py_hand", [a.name for a in self.client.list_assets()])
            with self.assertRaises(AlreadyExists):
                self.client.import_asset(path, name="py_hand")
            self.client.import_asset(path, name="py_hand", replace=True, precision="exact")
        clip = r.asset.clips[0].name
        p = self.client.evaluate_clip(clip, [0.5, 0.25], space="world")
        self.assertEqual(p.joint_names, ["Base", "Arm"])
        # t=0.5: Base at (1,2,3); Arm 2 above it, turned 90° about Z: q = (cos 45°, 0, 0, sin 45°).
        self.assertClose(p.translations[0], [[1, 2, 3], [1, 4, 3]], 1e-6, "hand BVH world positions at 0.5")
        h = np.sqrt(0.5)
        self.assertClose(p.rotations[0], [[1, 0, 0, 0], [h, 0, 0, h]], 1e-6, "hand BVH world rotations at 0.5")
        # t=0.25, linear: half the translation, 45° (slerp).
        self.assertClose(p.translations[1], [[0.5, 1, 1.5], [0.5, 3, 1.5]], 1e-6, "hand BVH positions at 0.25")
        c, s = np.cos(np.pi / 8), np.sin(np.pi / 8)
        self.assertClose(p.rotations[1, 1], [c, 0, 0, s], 1e-6, "hand BVH Arm rotation at 0.25")
        self.client.delete_asset("py_hand")
        with self.assertRaises(NotFound):
            self.client.evaluate_clip(clip, [0.0])

    def test_import_gltf_sends_its_buffer(self):
        corners = np.array([[0, 0, 0], [1, 0, 0], [0, 2, 0.5]], np.float32)
        gltf = {"asset": {"version": "2.0"}, "scene": 0, "scenes": [{"nodes": [0]}],
                "nodes": [{"mesh": 0}], "meshes": [{"name": "tri", "primitives": [{"attributes": {"POSITION": 0}}]}],
                "buffers": [{"uri": "tri%20data.bin", "byteLength": corners.nbytes}],
                "bufferViews": [{"buffer": 0, "byteLength": corners.nbytes}],
                "accessors": [{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
                               "min": corners.min(0).tolist(), "max": corners.max(0).tolist()}]}
        with tempfile.TemporaryDirectory() as d:
            os.makedirs(os.path.join(d, "scene"))
            path = os.path.join(d, "scene", "tri.gltf")
            with open(path, "w") as f:
                json.dump(gltf, f)
            corners.tofile(os.path.join(d, "scene", "tri data.bin"))
            r = self.client.import_asset(path, name="py_tri")
            mesh = r.asset.meshes[0]
            self.assertEqual(mesh.vertex_count, 3)
            positions, _, _ = self.client.get_mesh_geometry(mesh.name)
            np.testing.assert_array_equal(positions, corners)
            # A buffer outside the file's folder is not sent: refused before the call.
            gltf["buffers"][0]["uri"] = "../tri%20data.bin"
            corners.tofile(os.path.join(d, "tri data.bin"))
            with open(path, "w") as f:
                json.dump(gltf, f)
            with self.assertRaises(InvalidArgument) as e:
                self.client.import_asset(path, name="py_tri_outside")
            self.assertIn("../tri%20data.bin", e.exception.message)
        self.client.delete_asset("py_tri")

    def test_stream_clip_frames(self):
        fps, duration = 40.0, 0.5
        frames = list(self.client.stream_clip("demo_walk", fps=fps, duration=duration))
        print(f"  stream_clip: {len(frames)} frames at {fps} fps over {duration} s, last wall time "
              f"{frames[-1].wall_time:.3f} s")
        self.assertGreaterEqual(len(frames), int(fps * duration) - 1)
        self.assertLessEqual(len(frames), int(fps * duration) + 2)
        self.assertEqual([f.index for f in frames], list(range(len(frames))))
        self.assertTrue(all(b.time > a.time for a, b in zip(frames, frames[1:])))
        names = frames[0].joint_names
        self.assertTrue(names and all(f.joint_names == names for f in frames))
        ref = self.client.evaluate_clip("demo_walk", [f.time for f in frames])
        self.assertEqual(ref.joint_names, names)
        for i, f in enumerate(frames):
            self.assertEqual(f.translations.shape, (len(names), 3))
            self.assertEqual(f.rotations.shape, (len(names), 4))
            np.testing.assert_array_equal(f.translations, ref.translations[i])
            np.testing.assert_array_equal(f.rotations, ref.rotations[i])

    def test_stream_stops_when_the_caller_stops(self):
        stream = self.client.stream_clip("demo_walk", fps=60, loop=True)
        first = [next(stream) for _ in range(3)]
        stream.close()  # cancels the call: a looping stream would otherwise never end
        self.assertEqual([f.index for f in first], [0, 1, 2])
        open_streams = None
        for _ in range(100):  # the server sees the cancellation
            metrics = urllib.request.urlopen(f"http://127.0.0.1:{self.server.http_port}/metrics", timeout=10)
            open_streams = next(float(line.split()[-1]) for line in metrics.read().decode().splitlines()
                                if line.startswith("armature_streams_in_flight"))
            if open_streams == 0:
                break
            time.sleep(0.05)
        self.assertEqual(open_streams, 0, "the server still streams after the generator was closed")

    def test_skin_mesh_equals_the_cli(self):
        skinned = [m for m in self.client.list_meshes() if m.skeleton]
        self.assertTrue(skinned, "the demo character is a skinned mesh")
        mesh = skinned[0]
        clip = next(c.name for a in self.client.list_assets() for c in a.clips if c.skeleton == mesh.skeleton)
        s = self.client.skin_mesh(mesh.name, clip, 0.5)
        self.assertEqual(s.positions.shape, (mesh.vertex_count, 3))
        self.assertEqual(s.vertex_count, mesh.vertex_count)
        ref = self.cli("skin", mesh.name, "--clip", clip, "--time", "0.5")
        self.assertEqual(ref["vertexCount"], mesh.vertex_count)
        self.assertClose(s.positions, np.reshape(ref["positions"], (-1, 3)), 1e-9, f"{mesh.name} positions")
        if ref["normals"]:
            self.assertEqual(s.normals.shape, (mesh.vertex_count, 3))
            self.assertClose(s.normals, np.reshape(ref["normals"], (-1, 3)), 1e-9, f"{mesh.name} normals")
        dqs = self.client.skin_mesh(mesh.name, clip, 0.5, method="dqs")
        self.assertEqual(dqs.positions.shape, s.positions.shape)
        frames = list(self.client.stream_skinned_mesh(mesh.name, clip, fps=30, duration=0.2))
        self.assertTrue(frames)
        for f in frames:
            np.testing.assert_array_equal(f.positions, self.client.skin_mesh(mesh.name, clip, f.time).positions)
        print(f"  skin_mesh {mesh.name}: {mesh.vertex_count} vertices; {len(frames)} streamed frames")

    def test_evaluate_motion_equals_the_cli(self):
        motion = {"layers": [{"clip": "demo_walk", "weight": 1.0}, {"clip": "demo_walk", "weight": 0.5,
                                                                     "timeOffset": 0.3}],
                  "rootMotion": "IN_PLACE"}
        p = self.client.evaluate_motion(motion, TIMES, space="world")
        self.assertEqual(p.translations.shape, (len(TIMES), len(p.joint_names), 3))
        self.assertIsNone(p.root_translations)
        with tempfile.TemporaryDirectory() as d:
            path = os.path.join(d, "motion.json")
            with open(path, "w") as f:
                json.dump(motion, f)
            for i, t in enumerate(TIMES):
                ref = self.cli("pose", "--motion", path, "--time", repr(t), "--space", "world")
                self.assertEqual(p.joint_names, [j["name"] for j in ref["joints"]])
                self.assertClose(p.translations[i], [j["translation"] for j in ref["joints"]], 1e-9,
                                 f"motion translations at {t}")
                self.assertClose(p.rotations[i], [j["rotation"] for j in ref["joints"]], 1e-9,
                                 f"motion rotations at {t}")
        extract = self.client.evaluate_motion({"layers": [{"clip": "demo_walk"}], "rootMotion": "EXTRACT"}, TIMES)
        self.assertEqual(extract.root_translations.shape, (len(TIMES), 3))
        self.assertEqual(extract.root_rotations.shape, (len(TIMES), 4))
        with self.assertRaises(InvalidArgument) as e:
            self.client.evaluate_motion({"layers": [{"clip": "demo_walk", "blend": 1}]}, [0.0])
        self.assertIn("blend", e.exception.message)

    def test_solve_ik_reaches_a_reachable_target(self):
        # The target: where the last joint of the walk is at 0.5 s, reached from the pose at 0 s.
        at = self.client.evaluate_clip("demo_walk", [0.0, 0.5])
        skeleton = self.client.get_skeleton(at.skeleton)
        parents = {j.name: j.parent for j in skeleton.joints}
        end = next(n for n in reversed(at.joint_names) if parents[n] >= 0)
        k = at.joint_names.index(end)
        root_shift = at.translations[1, 0] - at.translations[0, 0]
        target = (at.translations[1, k] - root_shift).astype(float)  # the same reach, root held at 0 s
        r = self.client.solve_ik(at.skeleton, {end: target}, from_clip="demo_walk", time=0.0,
                                 position_tolerance=1e-5)
        got = r.world_translations[r.joint_names.index(end)]
        err = float(np.linalg.norm(got - target))
        print(f"  solve_ik {end}: converged={r.converged} stop={r.stop} iterations={r.iterations} error {err:.3g}")
        self.assertTrue(r.converged)
        self.assertLess(err, 2e-5)  # the tolerance, and float32 on the wire
        self.assertAlmostEqual(r.residuals[0].position_error, err, delta=1e-5)
        self.assertEqual(r.local_rotations.shape, (len(skeleton.joints), 4))

    def test_errors_are_typed(self):
        with self.assertRaises(NotFound) as e:
            self.client.evaluate_clip("no_such_clip", [0.0])
        self.assertIsInstance(e.exception, ArmatureError)
        self.assertEqual(e.exception.code, grpc.StatusCode.NOT_FOUND)
        self.assertIn("no_such_clip", e.exception.message)
        print(f"  unknown clip: {e.exception}")
        with self.assertRaises(InvalidArgument) as e:
            self.client.evaluate_clip("demo_walk", [-1.0])
        self.assertEqual(e.exception.code, grpc.StatusCode.INVALID_ARGUMENT)
        with self.assertRaises(InvalidArgument) as e:
            self.client.evaluate_clip("demo_walk", [0.0], space="sideways")
        self.assertIn("space", e.exception.message)
        with self.assertRaises(NotFound) as e:
            list(self.client.stream_clip("no_such_clip", fps=30))
        self.assertIn("no_such_clip", e.exception.message)
        with self.assertRaises(NotFound):
            self.client.skin_mesh("no_such_mesh", "demo_walk", 0.0)
        with self.assertRaises(DeadlineExceeded):
            list(self.client.stream_clip("demo_walk", fps=30, loop=True, timeout=0.3))
        with Client("127.0.0.1:1", timeout=2) as down:
            with self.assertRaises(Unavailable):
                down.list_assets()


class AuthTest(unittest.TestCase):
    def test_bearer_token(self):
        with tempfile.TemporaryDirectory() as d:
            token_file = os.path.join(d, "token")
            with open(token_file, "w") as f:
                f.write(TOKEN + "\n")
            with Server(SERVER_BIN, ["--auth-token-file", token_file]) as server:
                for token in (None, "wrong-token"):
                    with Client(server.target, token=token) as c:
                        with self.assertRaises(Unauthenticated) as e:
                            c.evaluate_clip("demo_walk", [0.0])
                        self.assertEqual(e.exception.code, grpc.StatusCode.UNAUTHENTICATED)
                with Client(server.target, token=TOKEN) as c:
                    self.assertEqual(c.evaluate_clip("demo_walk", [0.0]).translations.shape[0], 1)
                    self.assertEqual(len(list(c.stream_clip("demo_walk", fps=30, duration=0.1))) > 0, True)


class TlsTest(unittest.TestCase):
    def test_ca_file(self):
        if not shutil.which("openssl"):
            self.skipTest("openssl is not installed")
        with tempfile.TemporaryDirectory() as d:
            cert, key = os.path.join(d, "cert.pem"), os.path.join(d, "key.pem")
            subprocess.run(["openssl", "req", "-x509", "-newkey", "rsa:2048", "-nodes", "-days", "1", "-subj",
                            "/CN=localhost", "-addext", "subjectAltName=DNS:localhost,IP:127.0.0.1",
                            "-keyout", key, "-out", cert], check=True, capture_output=True)
            with Server(SERVER_BIN, ["--tls-cert", cert, "--tls-key", key]) as server:
                with Client(server.target, ca_file=cert) as c:
                    self.assertIn("demo_walk", [a.name for a in c.list_assets()])
                with Client(server.target, timeout=3) as plain:
                    with self.assertRaises(Unavailable):
                        plain.list_assets()


if __name__ == "__main__":
    print("armature_client from", armature_client.__file__)
    unittest.main(argv=sys.argv[:1], verbosity=2)
