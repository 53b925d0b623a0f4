"""armature_client: the Python client of the Armature animation server.

    from armature_client import Client
    c = Client("localhost:50051", token=None, timeout=30)
    poses = c.evaluate_clip("demo_walk", [0.0, 0.5], space="world")
    poses.translations.shape  # (2, joints, 3); poses.rotations (2, joints, 4); poses.joint_names
"""
from .client import Client
from .crowd import CrowdDecoder, CrowdFrame, CrowdSession
from .errors import (Aborted, AlreadyExists, ArmatureError, Cancelled, DataLoss, DeadlineExceeded,
                     FailedPrecondition, Internal, InvalidArgument, NotFound, OutOfRange, PermissionDenied,
                     ResourceExhausted, Unauthenticated, Unavailable, Unimplemented, Unknown)
from .results import IkResult, PoseFrame, Poses, SkinnedMesh

__version__ = "0.1.0"
__all__ = ["Client", "ArmatureError", "Aborted", "AlreadyExists", "Cancelled", "DataLoss", "DeadlineExceeded",
           "FailedPrecondition", "Internal", "InvalidArgument", "NotFound", "OutOfRange", "PermissionDenied",
           "ResourceExhausted", "Unauthenticated", "Unavailable", "Unimplemented", "Unknown", "IkResult",
           "PoseFrame", "Poses", "SkinnedMesh", "CrowdDecoder", "CrowdFrame", "CrowdSession"]
