"""Crowds (CrowdService): thousands of characters in one call, their poses
decoded to numpy arrays of LOCAL poses, as EvaluateClip's local space gives
them. The encoding is described in crowd.proto (CrowdLayout); the decoder is
the C++ client's armature/crowd_decoder.h, vectorised over characters."""
import math
import queue
import threading
from dataclasses import dataclass, field
from typing import List

import grpc
import numpy as np

from .errors import ArmatureError, FailedPrecondition, Internal, error_for, from_rpc_error

_HALF = math.sqrt(0.5)
# For each index of the largest component (x y z w), the other three in wire order.
_OTHERS = np.array([[i for i in range(4) if i != largest] for largest in range(4)], np.int64)


@dataclass
class CrowdFrame:
    """One tick: the characters it updates (most significant first).

    ids (n,) uint32; clip_times (n,) float64; rotations (n, joints, 4) as
    w, x, y, z; translations and scales (n, joints, 3), float32, LOCAL.
    `joints` is the most joints of the characters' layouts; a character with
    fewer is padded with identity transforms. errors: the commands refused
    since the last frame, as ArmatureErrors with `.id` (the character) and
    `.command` (its number, 1 = the first after the start). stats: the
    server's armature.v1.CrowdTickStats (characters, updated, deferred, ...).
    """
    tick: int
    time: float       # session time: tick / fps
    wall_time: float  # seconds since the first frame was due
    ids: np.ndarray
    clip_times: np.ndarray
    layouts: np.ndarray
    rotations: np.ndarray
    translations: np.ndarray
    scales: np.ndarray
    stats: object
    errors: List[ArmatureError] = field(default_factory=list)
    wire_bytes: int = 0  # the frame's serialized size


def _malformed(what):
    return Internal(grpc.StatusCode.INTERNAL, "crowd frame: " + what)


def _refusal(error):
    """A CrowdError as the typed error of its code, naming the character."""
    code = next((c for c in grpc.StatusCode if c.value[0] == error.code), grpc.StatusCode.UNKNOWN)
    e = error_for(code, error.error)
    e.id, e.command = error.id, error.message
    return e


def decode_rotations(raw):
    """(..., 6) uint8 smallest-three → (..., 4) float32 w, x, y, z (unit)."""
    bits = np.zeros(raw.shape[:-1], np.uint64)
    for i in range(6):
        bits |= raw[..., i].astype(np.uint64) << np.uint64(8 * i)
    largest = (bits & np.uint64(3)).astype(np.int64)
    three = np.stack([(bits >> np.uint64(2 + 15 * k)) & np.uint64(32767) for k in range(3)], axis=-1)
    three = three.astype(np.float64) / 32767 * (2 * _HALF) - _HALF
    xyzw = np.zeros(raw.shape[:-1] + (4,), np.float64)
    np.put_along_axis(xyzw, _OTHERS[largest], three, axis=-1)
    rest = np.sqrt(np.maximum(0.0, 1.0 - np.sum(three * three, axis=-1)))
    np.put_along_axis(xyzw, largest[..., None], rest[..., None], axis=-1)
    xyzw /= np.linalg.norm(xyzw, axis=-1, keepdims=True)
    return xyzw[..., [3, 0, 1, 2]].astype(np.float32)


class CrowdDecoder:
    """Keeps each clip's CrowdLayout from the frame that brought it; decode(frame) → CrowdFrame."""

    def __init__(self):
        self.layouts = {}

    def decode(self, frame):
        for layout in frame.new_layouts:
            self.layouts[layout.layout] = layout
        n = len(frame.ids)
        if len(frame.layouts) != n:
            raise _malformed("ids and layouts differ in count")
        numbers = np.asarray(frame.layouts, np.uint32)
        missing = set(numbers.tolist()) - set(self.layouts)
        if missing:
            raise _malformed(f"layout {min(missing)} never sent")
        joints = max((self.layouts[k].joints for k in set(numbers.tolist())), default=0)
        sizes = np.array([self.layouts[k].pose_bytes for k in numbers.tolist()], np.int64)
        starts = np.concatenate([[0], np.cumsum(sizes)[:-1]]) if n else sizes
        data = np.frombuffer(frame.poses, np.uint8)
        if int(sizes.sum()) != data.size:
            raise _malformed(f"{data.size} pose bytes where the ids need {int(sizes.sum())}")
        rotations = np.zeros((n, joints, 4), np.float32)
        rotations[..., 0] = 1  # padding: identity
        translations = np.zeros((n, joints, 3), np.float32)
        scales = np.ones((n, joints, 3), np.float32)
        for number in np.unique(numbers).tolist():
            rows = np.nonzero(numbers == number)[0]
            self._decode_layout(self.layouts[number], data, starts[rows], rows, rotations, translations, scales)
        return CrowdFrame(tick=frame.tick, time=frame.time, wall_time=frame.wall_time,
                          ids=np.asarray(frame.ids, np.uint32), clip_times=np.asarray(frame.clip_times, np.float64),
                          layouts=numbers, rotations=rotations, translations=translations, scales=scales,
                          stats=frame.stats, errors=[_refusal(e) for e in frame.errors],
                          wire_bytes=frame.ByteSize())

    @staticmethod
    def _decode_layout(layout, data, starts, rows, rotations, translations, scales):
        """The poses of the characters `rows` on one layout, at byte offsets `starts`."""
        j = layout.joints
        moved, scaled = np.asarray(layout.translated_joints, np.int64), np.asarray(layout.scaled_joints, np.int64)
        if len(layout.base_translations) != 3 * j or len(layout.base_scales) != 3 * j:
            raise _malformed(f"layout {layout.layout} has no base pose for its joints")
        if (moved.size and moved.max() >= j) or (scaled.size and scaled.max() >= j):
            raise _malformed(f"layout {layout.layout} names a joint past its {j}")
        if 6 * j + 12 * (moved.size + scaled.size) != layout.pose_bytes:
            raise _malformed(f"layout {layout.layout}'s pose_bytes disagree")
        poses = data[starts[:, None] + np.arange(layout.pose_bytes)]  # (m, pose_bytes)
        rotations[rows, :j] = decode_rotations(poses[:, :6 * j].reshape(-1, j, 6))
        rows_j = rows[:, None]
        translations[rows, :j] = np.asarray(layout.base_translations, np.float32).reshape(j, 3)
        scales[rows, :j] = np.asarray(layout.base_scales, np.float32).reshape(j, 3)
        vectors = np.ascontiguousarray(poses[:, 6 * j:]).view("<f4").reshape(len(rows), -1, 3)
        translations[rows_j, moved[None, :]] = vectors[:, :moved.size]
        scales[rows_j, scaled[None, :]] = vectors[:, moved.size:]


class CrowdSession:
    """A CrowdService.CrowdSession call: add, update and remove characters,
    read one CrowdFrame per tick from frames(). Made by Client.crowd_session.

    Commands go out in order on gRPC's request thread; a refused command does
    not end the session, it comes back in the next frame's `errors`. Without
    a `duration` the frames end once close() (or leaving the `with` block)
    has closed the sending side."""

    def __init__(self, call_method, start, metadata, timeout, crowd_pb2):
        self._pb = crowd_pb2
        self._queue = queue.Queue()
        self._closed = threading.Event()
        self._decoder = CrowdDecoder()
        self._queue.put(crowd_pb2.CrowdCommand(start=start))
        self._call = call_method(self._commands(), timeout=timeout, metadata=metadata)

    def _commands(self):
        while True:
            command = self._queue.get()
            if command is None:
                return
            yield command

    def _send(self, **command):
        if self._closed.is_set():
            raise FailedPrecondition(grpc.StatusCode.FAILED_PRECONDITION,
                                            "crowd session: commands after close()")
        self._queue.put(self._pb.CrowdCommand(**command))

    def _character(self, id, clip, skeleton, character, motion, time_offset, speed, root, significance):
        c = self._pb.CrowdCharacter(id=id, clip=clip or "", skeleton=skeleton or "", character=character or "",
                                    time_offset=float(time_offset), speed=float(speed),
                                    significance=float(significance))
        if motion is not None:
            from .client import _message  # the same motion forms as Client.evaluate_motion
            c.motion.CopyFrom(_message(type(c.motion), motion, "motion"))
        if root is not None:
            translation, rotation = root
            c.root.translation.extend(float(v) for v in (translation if translation is not None else ()))
            c.root.rotation.extend(float(v) for v in (rotation if rotation is not None else ()))
        return c

    def add(self, id, clip=None, skeleton=None, *, character=None, motion=None, time_offset=0.0, speed=1.0,
            root=None, significance=0.0):
        """A character: `clip` looped from `time_offset` at `speed`, on `skeleton` (default: the clip's).
        Or `motion` instead of a clip (a dict with motion.proto's JSON names, as Client.evaluate_motion
        takes, or a Motion message), blended at motion time time_offset + speed · t.
        root: (translation (3,) or None, rotation w, x, y, z or None), kept for the client to apply."""
        self._send(add=self._character(id, clip, skeleton, character, motion, time_offset, speed, root,
                                       significance))

    def update(self, id, clip=None, skeleton=None, *, character=None, motion=None, time_offset=0.0, speed=1.0,
               root=None, significance=0.0):
        """Replaces every field of character `id`."""
        self._send(update=self._character(id, clip, skeleton, character, motion, time_offset, speed, root,
                                          significance))

    def remove(self, id):
        self._send(remove=id)

    def close(self):
        """Closes the sending side: without a duration the frames end at the next tick."""
        if not self._closed.is_set():
            self._closed.set()
            self._queue.put(None)

    def cancel(self):
        self.close()
        self._call.cancel()

    def frames(self):
        """Yields a CrowdFrame per tick until the session ends; a failed call raises its ArmatureError."""
        try:
            for frame in self._call:
                yield self._decoder.decode(frame)
        except grpc.RpcError as e:
            if e.code() != grpc.StatusCode.CANCELLED or not self._closed.is_set():
                raise from_rpc_error(e) from None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.cancel()


def crowd_start(crowd_pb2, fps, budget_ms, max_interval, share_quantum, duration):
    return crowd_pb2.CrowdStart(fps=float(fps), budget_ms=float(budget_ms), max_interval=int(max_interval),
                                share_quantum=float(share_quantum), duration=float(duration))
