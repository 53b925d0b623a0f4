"""What calls return: the wire's packed floats as numpy arrays, with joint names."""
from dataclasses import dataclass, field
from typing import List, Optional

import numpy as np


def packed(values, width, count=None):
    """A repeated float field as a float32 array of shape (count, width)."""
    a = np.asarray(values, dtype=np.float32)
    return a.reshape((-1 if count is None else count, width))


def scales_of(pose, joints):
    """(joints, 3) scales: the pose's own, or ones when the wire left them out (all 1)."""
    if len(pose.scales):
        return packed(pose.scales, 3, joints)
    return np.ones((joints, 3), dtype=np.float32)


@dataclass
class Poses:
    """Poses at several times: EvaluateClip's and EvaluateMotion's answer.

    translations (times, joints, 3), rotations (times, joints, 4) as w, x, y, z,
    scales (times, joints, 3), all float32 as sent. In world space translations
    are joint positions. `joints` are the skeleton's indices of each entry,
    `joint_names` their names.
    """
    translations: np.ndarray
    rotations: np.ndarray
    scales: np.ndarray
    joint_names: List[str]
    joints: List[int]
    times: np.ndarray
    skeleton: str
    space: str
    clip: str = ""
    # EvaluateMotion with rootMotion EXTRACT: (times, 3) and (times, 4), else None.
    root_translations: Optional[np.ndarray] = None
    root_rotations: Optional[np.ndarray] = None


@dataclass
class PoseFrame:
    """One frame of stream_clip: translations (joints, 3), rotations (joints, 4)."""
    index: int
    time: float       # clip time
    wall_time: float  # seconds since the stream started
    translations: np.ndarray
    rotations: np.ndarray
    scales: np.ndarray
    joint_names: List[str]
    joints: List[int]
    skeleton: str


@dataclass
class SkinnedMesh:
    """positions (vertices, 3) in world space; normals (vertices, 3) or None when the mesh has none."""
    mesh: str
    positions: np.ndarray
    normals: Optional[np.ndarray]
    time: float = 0.0
    index: int = 0        # stream_skinned_mesh: the frame's index
    wall_time: float = 0.0

    @property
    def vertex_count(self):
        return self.positions.shape[0]


@dataclass
class IkResult:
    """solve_ik's answer: the solved pose, local and world, (joints, 3) and (joints, 4)."""
    skeleton: str
    joint_names: List[str]
    local_translations: np.ndarray
    local_rotations: np.ndarray
    world_translations: np.ndarray
    world_rotations: np.ndarray
    converged: bool
    stop: str
    iterations: int
    residuals: list = field(default_factory=list)  # armature.v1.IkResidual, one per effector
