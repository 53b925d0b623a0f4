"""armature_client's crowds (Client.crowd_session, Client.watch_crowd) against
a real armature-server on CMU 01_01 from ../shared/data.

The reference is the server's EvaluateClip in LOCAL space at each character's
clip time: decoded poses must equal it within the encoding's stated error
(CrowdLayout.max_rotation_error, 1.495e-4 rad) plus CMU's compression bound,
derived as the C++ Crowd.* integration test derives it. The clip times
themselves are checked against offset + speed · time, wrapped to the clip.

usage: test_crowd.py PYTHON SERVER_BIN
PYTHON is the interpreter the package is installed in (python_client.install_offline's venv).
"""
import math
import os
import sys
import unittest

from client_python import run_in_client_python  # noqa: E402

run_in_client_python()

import numpy as np  # noqa: E402

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "reference"))
from server_fixture import Server  # noqa: E402

from armature_client import AlreadyExists, Client, InvalidArgument, NotFound, ResourceExhausted  # noqa: E402

SERVER_BIN = sys.argv[2]
CMU = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "..", "..", "shared", "data", "bvh",
                   "cmu_01_01.bvh")
# CMU's compression bound (0.01 units at a 3-unit shell, the default for a BVH body of its span) as a
# local rotation: a joint's error moves a shell point by at least its angle × 3; twice that for margin.
COMPRESSION_ANGLE = 2 * 0.01 / 3
TRANSLATION_TOLERANCE = 0.02  # the bound's 0.01 units at the hips, with float rounding
SHARE_QUANTUM = 1 / 120       # the server's default: clip times rounded to it


def angles(a, b):
    """Per-quaternion rotation angle between (..., 4) arrays, sign-blind. From the chord
    (4·asin(|a ∓ b| / 2)), not acos of the dot, which float32 rounding swamps near 0."""
    a, b = np.asarray(a, np.float64), np.asarray(b, np.float64)
    a = a / np.linalg.norm(a, axis=-1, keepdims=True)
    b = b / np.linalg.norm(b, axis=-1, keepdims=True)
    chord = np.minimum(np.linalg.norm(a - b, axis=-1), np.linalg.norm(a + b, axis=-1))
    return 4 * np.arcsin(np.minimum(1.0, chord / 2))


def offset_of(i):
    return 0.53 * i


def speed_of(i):
    return 0.5 + 0.05 * i


@unittest.skipUnless(os.path.exists(CMU), "../shared/data/bvh/cmu_01_01.bvh is absent")
class CrowdTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.server = Server(SERVER_BIN, ["--max-crowd-characters", "50"])
        cls.client = Client(cls.server.target, timeout=60)
        cls.client.import_asset(CMU, "cmu")
        cls.duration = cls.client.get_clip("cmu").duration
        cls.joints = len(cls.client.joint_names(cls.client.evaluate_clip("cmu", [0]).skeleton))

    @classmethod
    def tearDownClass(cls):
        cls.client.close()
        cls.server.stop()

    def compare(self, frame):
        """Worst (rotation angle, translation difference, clip time difference) of a frame's characters."""
        ref = self.client.evaluate_clip("cmu", frame.clip_times, space="local")
        self.assertEqual(frame.rotations.shape, (len(frame.ids), self.joints, 4))
        self.assertEqual(frame.translations.shape, (len(frame.ids), self.joints, 3))
        expected = np.array([offset_of(i) + speed_of(i) * frame.time for i in frame.ids.tolist()]) % self.duration
        time_error = np.abs(frame.clip_times - expected)
        time_error = np.minimum(time_error, self.duration - time_error)  # across the loop's seam
        return (float(angles(frame.rotations, ref.rotations).max()),
                float(np.abs(frame.translations - ref.translations).max()), float(time_error.max()))

    def test_decoded_poses_are_evaluate_clips_local_poses(self):
        worst = np.zeros(3)
        frames = compared = 0
        with self.client.crowd_session(fps=30, duration=0.5) as s:
            for i in range(40):
                s.add(id=i, clip="cmu", time_offset=offset_of(i), speed=speed_of(i), significance=-i)
            s.close()
            for f in s.frames():
                frames += 1
                self.assertEqual(f.errors, [])
                self.assertAlmostEqual(f.time, f.tick / 30, places=9)
                self.assertEqual(f.stats.updated, len(f.ids))
                if len(f.ids):
                    stated = s._decoder.layouts[int(f.layouts[0])].max_rotation_error
                    worst = np.maximum(worst, self.compare(f))
                    compared += len(f.ids)
        print(f"  {frames} frames, {compared} poses: worst rotation {worst[0]:.3g} rad (stated {stated:.4g}), "
              f"translation {worst[1]:.3g}, clip time {worst[2]:.3g} s")
        self.assertEqual(frames, 15)  # 0.5 s at 30 fps
        self.assertGreaterEqual(compared, 40)
        self.assertAlmostEqual(stated, 4 * math.asin(math.sqrt(3) * math.sqrt(2) / 65534), places=9)
        self.assertLessEqual(worst[0], stated + COMPRESSION_ANGLE)
        self.assertLessEqual(worst[1], TRANSLATION_TOLERANCE)
        self.assertLessEqual(worst[2], SHARE_QUANTUM / 2 + 1e-9)

    def test_a_duplicate_id_names_the_character_and_the_session_runs_on(self):
        refused, ids_seen, characters = [], set(), 0
        with self.client.crowd_session(fps=30) as s:
            s.add(id=1, clip="cmu")
            s.add(id=1, clip="cmu", time_offset=0.2)  # duplicate
            s.add(id=2, clip="cmu", time_offset=float("nan"))
            s.remove(9)
            s.add(id=3, clip="cmu", time_offset=0.4)  # after the refusals: still taken
            for f in s.frames():
                refused += f.errors
                ids_seen.update(f.ids.tolist())
                characters = f.stats.characters
                if f.tick == 5:
                    s.close()  # no duration: the frames end at the next tick
        self.assertEqual([type(e) for e in refused], [AlreadyExists, InvalidArgument, NotFound])
        self.assertEqual([e.id for e in refused], [1, 2, 9])
        for e in refused:
            self.assertTrue(e.message.startswith(f"character {e.id}: "), e.message)
        self.assertEqual([e.command for e in refused], [2, 3, 4])
        self.assertEqual(ids_seen, {1, 3})
        self.assertEqual(characters, 2)

    def test_a_motion_character_poses_are_evaluate_motions(self):
        """Two layers of CMU 0.3 / 0.7 (the second 0.6 s ahead): poses equal evaluate_motion's at
        each motion time within the stated error (the same stored clips: no compression term);
        a NaN weight is refused naming the character."""
        motion = {"layers": [{"clip": "cmu", "weight": 0.3}, {"clip": "cmu", "weight": 0.7, "timeOffset": 0.6}]}
        worst, compared, refused = np.zeros(2), 0, []
        with self.client.crowd_session(fps=30, duration=0.3) as s:
            for i in range(5):
                s.add(id=i, motion=motion, time_offset=0.4 * i, speed=1 + 0.2 * i)
            s.add(id=9, motion={"layers": [{"clip": "cmu", "weight": "NaN"}]})  # proto3 JSON spells NaN so
            s.close()
            for f in s.frames():
                refused += f.errors
                if not len(f.ids):
                    continue
                stated = s._decoder.layouts[int(f.layouts[0])].max_rotation_error
                expected = np.array([0.4 * i + (1 + 0.2 * i) * f.time for i in f.ids.tolist()])
                np.testing.assert_allclose(f.clip_times, expected, atol=SHARE_QUANTUM / 2 + 1e-9)
                ref = self.client.evaluate_motion(motion, f.clip_times, space="local")
                worst = np.maximum(worst, [angles(f.rotations, ref.rotations).max(),
                                           np.abs(f.translations - ref.translations).max()])
                compared += len(f.ids)
        print(f"  motion: {compared} poses, worst rotation {worst[0]:.3g} rad (stated {stated:.4g}), "
              f"translation {worst[1]:.3g}")
        self.assertGreaterEqual(compared, 5 * 5)
        self.assertLessEqual(worst[0], stated + 1e-5)  # float32 on both sides
        self.assertLessEqual(worst[1], 1e-4)
        self.assertEqual([(type(e), e.id) for e in refused], [(InvalidArgument, 9)])
        self.assertTrue(refused[0].message.startswith("character 9: motion"), refused[0].message)

    def test_watch_crowd_streams_the_same_poses(self):
        characters = [{"id": i, "clip": "cmu", "timeOffset": offset_of(i), "speed": speed_of(i)} for i in range(12)]
        frames = list(self.client.watch_crowd(characters, fps=30, max_ticks=6))
        self.assertEqual([f.tick for f in frames], list(range(6)))
        self.assertEqual(sorted(set(np.concatenate([f.ids for f in frames]).tolist())), list(range(12)))
        for f in frames:
            if len(f.ids):
                rotation, translation, clip_time = self.compare(f)
                self.assertLessEqual(rotation, 1.5e-4 + COMPRESSION_ANGLE)
                self.assertLessEqual(translation, TRANSLATION_TOLERANCE)
                self.assertLessEqual(clip_time, SHARE_QUANTUM / 2 + 1e-9)

    def test_watch_crowd_refuses_bad_input_before_any_frame(self):
        with self.assertRaises(InvalidArgument) as e:
            list(self.client.watch_crowd([{"id": 1, "clip": "cmu"}, {"id": 7, "clip": "cmu", "speed": "NaN"}],
                                         max_ticks=3))
        self.assertIn("character 7: ", e.exception.message)
        with self.assertRaises(ResourceExhausted) as e:
            list(self.client.watch_crowd([{"id": i, "clip": "cmu"} for i in range(51)], max_ticks=3))
        self.assertIn("--max-crowd-characters", e.exception.message)


if __name__ == "__main__":
    unittest.main(argv=sys.argv[:1], verbosity=2)
