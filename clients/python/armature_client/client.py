"""Client: the Armature API over gRPC, answers as numpy arrays."""
import json
import os
import urllib.parse

import grpc
import numpy as np
from google.protobuf import json_format

from . import errors
from .crowd import CrowdDecoder, CrowdSession, crowd_start
from .results import IkResult, PoseFrame, Poses, SkinnedMesh, packed, scales_of

try:
    from ._proto.armature.v1 import (assets_pb2, assets_pb2_grpc, crowd_pb2, crowd_pb2_grpc, ik_pb2, ik_pb2_grpc, meshes_pb2,
                                     meshes_pb2_grpc, motion_pb2, poses_pb2, poses_pb2_grpc, types_pb2)
except ImportError as e:  # the source tree, not an installed package
    raise ImportError("armature_client: the generated gRPC stubs are missing; install the package "
                      "(python3 -m pip install --no-build-isolation ./clients/python) or run "
                      "clients/python/generate_stubs.py armature_client/_proto") from e

_MAX_MESSAGE = 512 << 20
_CHUNK = 1 << 20


def _invalid(message):
    return errors.InvalidArgument(grpc.StatusCode.INVALID_ARGUMENT, message)


def _enum(wrapper, value, field):
    """An enum from its name in any case ("world", "LBS", "two_bone"), its number, or None (unspecified)."""
    if value is None:
        return 0
    if isinstance(value, (int, np.integer)):
        return int(value)
    try:
        return wrapper.Value(str(value).upper().replace("-", "_"))
    except ValueError:
        choices = ", ".join(n.lower() for n in wrapper.keys() if not n.endswith("UNSPECIFIED"))
        raise _invalid(f"{field}: '{value}' is not one of {choices}") from None


def _times(times, field="times"):
    a = np.atleast_1d(np.asarray(times, dtype=np.float64)).ravel()
    if not np.all(np.isfinite(a)):
        raise _invalid(f"{field}: every time must be finite")
    return a.tolist()


def _message(cls, value, field):
    """A request sub-message from a message, a dict (proto3 JSON names or field names) or JSON text."""
    if isinstance(value, cls):
        return value
    try:
        if isinstance(value, (str, bytes)):
            return json_format.Parse(value, cls())
        return json_format.ParseDict(value, cls())
    except (json_format.ParseError, TypeError, ValueError) as e:
        raise _invalid(f"{field}: {e}") from None


class Client:
    """A connection to an armature-server's gRPC port.

    Client("host:50051", token=None, timeout=30): `timeout` is the deadline in
    seconds of every unary call; streams get `stream_timeout` (default one
    hour) unless a call passes its own `timeout`. `token` is sent as
    `authorization: Bearer TOKEN`; `ca_file` (PEM) switches to TLS trusting
    that CA, `tls_server_name` overrides the name the certificate must carry.
    Every failure raises an armature_client.ArmatureError subclass (NotFound,
    InvalidArgument, Unauthenticated, ...) with `.code` and `.message`.
    """

    def __init__(self, target, token=None, timeout=30, *, ca_file=None, tls_server_name=None,
                 stream_timeout=3600, channel_options=()):
        self.target = target
        self.timeout = float(timeout)
        self.stream_timeout = float(stream_timeout)
        options = [("grpc.max_receive_message_length", _MAX_MESSAGE),
                   ("grpc.max_send_message_length", _MAX_MESSAGE), *channel_options]
        if ca_file:
            with open(ca_file, "rb") as f:
                credentials = grpc.ssl_channel_credentials(root_certificates=f.read())
            if tls_server_name:
                options.append(("grpc.ssl_target_name_override", tls_server_name))
            self._channel = grpc.secure_channel(target, credentials, options)
        else:
            self._channel = grpc.insecure_channel(target, options)
        self._metadata = ()
        if token:
            self._metadata = (("authorization", token if token.startswith("Bearer ") else "Bearer " + token),)
        self._assets = assets_pb2_grpc.AssetServiceStub(self._channel)
        self._poses = poses_pb2_grpc.PoseServiceStub(self._channel)
        self._meshes = meshes_pb2_grpc.MeshServiceStub(self._channel)
        self._ik = ik_pb2_grpc.IkServiceStub(self._channel)
        self._crowds = crowd_pb2_grpc.CrowdServiceStub(self._channel)
        self._joint_names_by_skeleton = {}

    def close(self):
        self._channel.close()

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # -- plumbing -----------------------------------------------------------
    def _unary(self, method, request, timeout):
        try:
            return method(request, timeout=self.timeout if timeout is None else timeout, metadata=self._metadata)
        except grpc.RpcError as e:
            raise errors.from_rpc_error(e) from None

    def _stream(self, method, request, timeout):
        call = method(request, timeout=self.stream_timeout if timeout is None else timeout, metadata=self._metadata)
        try:
            for message in call:
                yield message
        except grpc.RpcError as e:
            raise errors.from_rpc_error(e) from None
        finally:
            call.cancel()  # the caller stopped early: end the stream on the server too

    def joint_names(self, skeleton, timeout=None):
        """The skeleton's joint names in index order (fetched once, then cached;
        forget_skeletons() drops the cache, e.g. after another client re-imported)."""
        names = self._joint_names_by_skeleton.get(skeleton)
        if names is None:
            names = [j.name for j in self.get_skeleton(skeleton, timeout=timeout).joints]
            self._joint_names_by_skeleton[skeleton] = names
        return names

    def forget_skeletons(self):
        self._joint_names_by_skeleton.clear()

    def _names(self, skeleton, joints, timeout):
        names = self.joint_names(skeleton, timeout)
        if joints and max(joints) >= len(names):  # the skeleton changed since it was cached
            self._joint_names_by_skeleton.pop(skeleton, None)
            names = self.joint_names(skeleton, timeout)
        return [names[j] for j in joints]

    def _poses_result(self, skeleton, joints, times, poses, space, timeout, clip="", root_motion=()):
        joints = list(joints)
        n, count = len(joints), len(poses)
        result = Poses(
            translations=np.empty((count, n, 3), np.float32), rotations=np.empty((count, n, 4), np.float32),
            scales=np.empty((count, n, 3), np.float32), joint_names=self._names(skeleton, joints, timeout),
            joints=joints, times=np.asarray(times, np.float64), skeleton=skeleton,
            space=types_pb2.Space.Name(space).lower(), clip=clip)
        for i, pose in enumerate(poses):
            result.translations[i] = packed(pose.translations, 3, n)
            result.rotations[i] = packed(pose.rotations, 4, n)
            result.scales[i] = scales_of(pose, n)
        if len(root_motion):
            result.root_translations = np.stack([packed(p.translations, 3, 1)[0] for p in root_motion])
            result.root_rotations = np.stack([packed(p.rotations, 4, 1)[0] for p in root_motion])
        return result

    # -- assets -------------------------------------------------------------
    def list_assets(self, timeout=None):
        """Every asset (armature.v1.AssetInfo: name, format, skeletons, clips, meshes)."""
        return list(self._unary(self._assets.ListAssets, assets_pb2.ListAssetsRequest(), timeout).assets)

    def list_clips(self, timeout=None):
        return list(self._unary(self._assets.ListClips, assets_pb2.ListClipsRequest(), timeout).clips)

    def list_meshes(self, timeout=None):
        return list(self._unary(self._meshes.ListMeshes, meshes_pb2.ListMeshesRequest(), timeout).meshes)

    def get_clip(self, clip, timeout=None):
        return self._unary(self._assets.GetClip, assets_pb2.GetClipRequest(clip=clip), timeout)

    def get_skeleton(self, skeleton, timeout=None):
        """armature.v1.Skeleton: joints with name, parent, offset, rest rotation."""
        return self._unary(self._assets.GetSkeleton, assets_pb2.GetSkeletonRequest(skeleton=skeleton), timeout)

    def delete_asset(self, name, timeout=None):
        self.forget_skeletons()
        return self._unary(self._assets.DeleteAsset, assets_pb2.DeleteAssetRequest(name=name), timeout)

    def import_asset(self, path, name=None, *, format=None, replace=False, resources=None, precision=None,
                     timeout=None):
        """Uploads a BVH, glTF/GLB, OBJ or FBX file; returns armature.v1.ImportAssetResponse (.asset, .warnings).

        A .gltf's external buffers and images are sent too when they are files
        in its folder (or below); `resources` ({uri: path}) names others.
        `precision`: "exact", a bound in centimetres (0.01), or None for the
        server's --clip-error."""
        with open(path, "rb") as f:
            main = f.read()
        extra = dict(resources or {})
        if path.lower().endswith(".gltf") and resources is None:
            extra = _gltf_resources(path, main)
        for uri, file in extra.items():  # fail here, not inside gRPC's request thread
            if not os.path.isfile(file):
                raise FileNotFoundError(f"resource '{uri}': no file {file}")

        def requests():
            first = True
            for chunk in _chunks(main):
                if first:
                    yield assets_pb2.ImportAssetRequest(filename=os.path.basename(path), name=name or "",
                                                        format=format or "", replace=replace, data=chunk,
                                                        precision="" if precision is None else str(precision))
                    first = False
                else:
                    yield assets_pb2.ImportAssetRequest(data=chunk)
            for uri, file in extra.items():
                with open(file, "rb") as f:
                    data = f.read()
                for i, chunk in enumerate(_chunks(data)):
                    yield assets_pb2.ImportAssetRequest(resource=uri if i == 0 else "", data=chunk)

        self.forget_skeletons()
        return self._unary(self._assets.ImportAsset, requests(), timeout)

    # -- poses --------------------------------------------------------------
    def evaluate_clip(self, clip, times, space="world", *, interpolation=None, wrap=None, joints=None,
                      timeout=None):
        """The clip's poses at `times` (seconds): a Poses with .translations (times, joints, 3),
        .rotations (times, joints, 4) (w, x, y, z) and .joint_names."""
        request = poses_pb2.EvaluateClipRequest(
            clip=clip, times=_times(times), space=_enum(types_pb2.Space, space, "space"),
            interpolation=_enum(types_pb2.Interpolation, interpolation, "interpolation"),
            wrap=_enum(types_pb2.WrapMode, wrap, "wrap"), joints=list(joints or []))
        r = self._unary(self._poses.EvaluateClip, request, timeout)
        return self._poses_result(r.skeleton, r.joints, r.times, r.poses, r.space, timeout, clip=r.clip)

    def evaluate_motion(self, motion, times, space="world", *, joints=None, timeout=None):
        """A motion (clips in layers; a dict with motion.proto's JSON names such as
        {"layers": [{"clip": "walk", "weight": 0.5}, ...], "rootMotion": "EXTRACT"}) at `times`.
        With EXTRACT, .root_translations (times, 3) and .root_rotations (times, 4) hold the root motion."""
        request = poses_pb2.EvaluateMotionRequest(
            motion=_message(motion_pb2.Motion, motion, "motion"), times=_times(times),
            space=_enum(types_pb2.Space, space, "space"), joints=list(joints or []))
        r = self._unary(self._poses.EvaluateMotion, request, timeout)
        return self._poses_result(r.skeleton, r.joints, r.times, r.poses, r.space, timeout, root_motion=r.root_motion)

    def stream_clip(self, clip, fps=30, *, speed=1.0, loop=False, start_time=0.0, duration=0.0, space="world",
                    interpolation=None, joints=None, timeout=None):
        """Plays the clip: yields a PoseFrame (.translations (joints, 3), .rotations (joints, 4), .time)
        paced in real time at `fps`. Stop iterating (or close the generator) to end the stream."""
        request = poses_pb2.StreamClipRequest(
            clip=clip, fps=fps, speed=speed, loop=loop, start_time=start_time, duration=duration,
            space=_enum(types_pb2.Space, space, "space"),
            interpolation=_enum(types_pb2.Interpolation, interpolation, "interpolation"), joints=list(joints or []))
        skeleton, indices, names = "", [], []
        for frame in self._stream(self._poses.StreamClip, request, timeout):
            if frame.skeleton:
                skeleton, indices = frame.skeleton, list(frame.joints)
                names = self._names(skeleton, indices, None)
            n = len(frame.pose.rotations) // 4
            yield PoseFrame(index=frame.index, time=frame.time, wall_time=frame.wall_time,
                            translations=packed(frame.pose.translations, 3, n),
                            rotations=packed(frame.pose.rotations, 4, n), scales=scales_of(frame.pose, n),
                            joint_names=names, joints=indices, skeleton=skeleton)

    # -- crowds -------------------------------------------------------------
    def crowd_session(self, fps=30, *, budget_ms=0.0, max_interval=0, share_quantum=0.0, duration=0.0,
                      timeout=None):
        """A crowd: `with client.crowd_session(fps=30) as s: s.add(id=..., skeleton=..., clip=...,
        time_offset=...)`, then `for f in s.frames():` (a CrowdFrame: f.ids, f.rotations (n, joints, 4),
        f.translations (n, joints, 3) as LOCAL poses, f.time, f.clip_times, f.stats, f.errors).
        budget_ms 0 = the server's --crowd-budget-ms; duration 0 = until s.close()."""
        start = crowd_start(crowd_pb2, fps, budget_ms, max_interval, share_quantum, duration)
        return CrowdSession(self._crowds.CrowdSession, start, self._metadata,
                            self.stream_timeout if timeout is None else timeout, crowd_pb2)

    def watch_crowd(self, characters, fps=30, *, budget_ms=0.0, max_interval=0, share_quantum=0.0, duration=0.0,
                    max_ticks=0, timeout=None):
        """A read-only crowd (WatchCrowd, which gRPC-Web can carry): `characters` are dicts of
        CrowdCharacter's fields ({"id": 1, "clip": "walk", "timeOffset": 0.5}); yields CrowdFrames."""
        request = crowd_pb2.WatchCrowdRequest(
            start=crowd_start(crowd_pb2, fps, budget_ms, max_interval, share_quantum, duration),
            characters=[_message(crowd_pb2.CrowdCharacter, c, f"characters[{i}]") for i, c in enumerate(characters)],
            max_ticks=max_ticks)
        decoder = CrowdDecoder()
        for frame in self._stream(self._crowds.WatchCrowd, request, timeout):
            yield decoder.decode(frame)

    # -- meshes -------------------------------------------------------------
    def get_mesh_geometry(self, mesh, timeout=None):
        """The rest mesh: (positions (vertices, 3), normals (vertices, 3) or None, triangles (triangles, 3))."""
        r = self._unary(self._meshes.GetMeshGeometry, meshes_pb2.GetMeshGeometryRequest(mesh=mesh), timeout)
        positions = packed(r.positions, 3, r.vertex_count)
        normals = packed(r.normals, 3, r.vertex_count) if len(r.normals) else None
        return positions, normals, np.asarray(r.triangles, np.uint32).reshape((-1, 3))

    def get_mesh_uvs(self, mesh, timeout=None):
        """The rest mesh's texture coordinates (vertices, 2), or None when it has none."""
        r = self._unary(self._meshes.GetMeshGeometry, meshes_pb2.GetMeshGeometryRequest(mesh=mesh), timeout)
        return packed(r.uvs, 2, r.vertex_count) if len(r.uvs) else None

    def get_material(self, mesh, material=0, timeout=None):
        """Material `material` of the mesh (a Material message: factors, textures, images' types and sizes)."""
        return self._unary(self._meshes.GetMaterial,
                           meshes_pb2.GetMaterialRequest(mesh=mesh, material=material), timeout)

    def get_material_image(self, mesh, material, image, timeout=None):
        """One image of a material as stored in the imported file: (mime_type, bytes)."""
        r = self._unary(self._meshes.GetMaterialImage,
                        meshes_pb2.GetMaterialImageRequest(mesh=mesh, material=material, image=image), timeout)
        return r.mime_type, r.data

    def skin_mesh(self, mesh, clip="", time=0.0, *, method="lbs", interpolation=None, wrap=None,
                  morph_weights=None, timeout=None):
        """The mesh skinned by the clip's pose at `time`: .positions (vertices, 3) in world space,
        .normals (vertices, 3) or None. method: "lbs" or "dqs"."""
        request = meshes_pb2.SkinMeshRequest(
            mesh=mesh, clip=clip, time=time, method=_enum(meshes_pb2.SkinningMethod, method, "method"),
            interpolation=_enum(types_pb2.Interpolation, interpolation, "interpolation"),
            wrap=_enum(types_pb2.WrapMode, wrap, "wrap"), morph_weights=list(morph_weights or []))
        r = self._unary(self._meshes.SkinMesh, request, timeout)
        return _skinned(r.mesh, r.vertex_count, r.positions, r.normals, time=time)

    def stream_skinned_mesh(self, mesh, clip, fps=30, *, speed=1.0, loop=False, start_time=0.0, duration=0.0,
                            method="lbs", interpolation=None, timeout=None):
        """Plays the clip on the mesh: yields a SkinnedMesh per frame."""
        request = meshes_pb2.StreamSkinnedMeshRequest(
            mesh=mesh, clip=clip, fps=fps, speed=speed, loop=loop, start_time=start_time, duration=duration,
            method=_enum(meshes_pb2.SkinningMethod, method, "method"),
            interpolation=_enum(types_pb2.Interpolation, interpolation, "interpolation"))
        for frame in self._stream(self._meshes.StreamSkinnedMesh, request, timeout):
            yield _skinned(mesh, len(frame.positions) // 3, frame.positions, frame.normals, time=frame.time,
                           index=frame.index, wall_time=frame.wall_time)

    # -- inverse kinematics -------------------------------------------------
    def solve_ik(self, skeleton, targets, *, solver="dls", from_clip=None, time=0.0, root="", max_iterations=0,
                 position_tolerance=0.0, timeout=None):
        """One IK solve. `targets`: {joint: (x, y, z)} world positions, or a list of IkEffector dicts
        ({"joint": ..., "target_position": [...], "target_rotation": [w, x, y, z], ...}).
        Starts from the rest pose, or from `from_clip` at `time`. position_tolerance 0 is the server's
        default (1e-4 of the chain length). Returns an IkResult."""
        if isinstance(targets, dict):
            effectors = [ik_pb2.IkEffector(joint=j, target_position=list(map(float, p))) for j, p in targets.items()]
        else:
            effectors = [_message(ik_pb2.IkEffector, e, f"targets[{i}]") for i, e in enumerate(targets)]
        request = ik_pb2.SolveIkRequest(skeleton=skeleton, solver=_enum(ik_pb2.IkSolver, solver, "solver"),
                                        effectors=effectors, root=root,
                                        options=ik_pb2.IkOptions(max_iterations=max_iterations,
                                                                         position_tolerance=position_tolerance))
        if from_clip:
            request.from_clip.CopyFrom(ik_pb2.ClipTime(clip=from_clip, time=time))
        r = self._unary(self._ik.SolveIk, request, timeout)
        joints = list(r.joints)
        n = len(joints)
        return IkResult(skeleton=r.skeleton, joint_names=self._names(r.skeleton, joints, timeout),
                        local_translations=packed(r.local.translations, 3, n),
                        local_rotations=packed(r.local.rotations, 4, n),
                        world_translations=packed(r.world.translations, 3, n),
                        world_rotations=packed(r.world.rotations, 4, n), converged=r.converged,
                        stop=ik_pb2.IkStop.Name(r.stop), iterations=r.iterations, residuals=list(r.residuals))


def _skinned(mesh, vertex_count, positions, normals, **kw):
    return SkinnedMesh(mesh=mesh, positions=packed(positions, 3, vertex_count),
                       normals=packed(normals, 3, vertex_count) if len(normals) else None, **kw)


def _chunks(data):
    if not data:
        yield b""
    for i in range(0, len(data), _CHUNK):
        yield data[i:i + _CHUNK]


def _gltf_resources(path, text):
    """The .gltf's external buffer and image files in its folder, {uri: path}. A uri
    out of the folder (absolute, "..", a symlink out) is refused: a .gltf must not
    make the client send the user's other files."""
    folder = os.path.realpath(os.path.dirname(os.path.abspath(path)))
    try:
        doc = json.loads(text)
    except ValueError as e:
        raise _invalid(f"{path}: not JSON ({e})") from None
    out = {}
    for kind in ("buffers", "images"):
        for item in doc.get(kind) or []:
            uri = item.get("uri") if isinstance(item, dict) else None
            if not uri or uri.startswith("data:") or "://" in uri or uri in out:
                continue
            file = os.path.realpath(os.path.join(folder, urllib.parse.unquote(uri)))
            if os.path.isabs(urllib.parse.unquote(uri)) or os.path.commonpath([folder, file]) != folder:
                raise _invalid(f"{path}: {kind} uri '{uri}' is outside the file's folder; pass it in resources=")
            if os.path.isfile(file):
                out[uri] = file
    return out
