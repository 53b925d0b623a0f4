#include "server/pose/pose_handlers.h"

#include "armature/engine/anim/clip.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "server/assets/motion_convert.h"
#include "server/rpc/convert/pose_convert.h"
#include "server/rpc/request_validation.h"

namespace armature::server {
namespace {

// Each pose carries 7 floats per listed joint (a repeated joint counts
// again) and its time; refused before any pose is computed.
Status ValidatePosesReplySize(int times, size_t joints, const Limits& limits, ReplyEncoding encoding,
                              const std::string& rpc, const std::string& alternative) {
  ReplyContent reply;
  reply.floats = static_cast<double>(times) * static_cast<double>(joints) * 7;
  reply.doubles = times;
  reply.proto_overhead = static_cast<double>(times) * 8;
  // {"translations":[],"rotations":[],"scales":[]}, per pose; each joint index.
  reply.json_overhead = static_cast<double>(times) * 48 + static_cast<double>(joints) * 4;
  reply.how = std::to_string(times) + " times x " + std::to_string(joints) + " joints x 7 floats";
  return ValidateReplySize(reply, encoding, limits, rpc, alternative);
}

// The joints of `clip`'s skeleton, 0 when there is no such clip.
int64_t SkeletonJointsOf(const Catalog& catalog, const std::string& clip) {
  auto ref = catalog.FindClip(clip);
  return ref.ok() ? static_cast<int64_t>(ref->part->runtime->skeleton->size()) : 0;
}

}  // namespace

RequestWork EvaluateClipWork(const Catalog& catalog, const v1::EvaluateClipRequest& request) {
  return {1, request.times_size(), SkeletonJointsOf(catalog, request.clip())};
}

RequestWork EvaluateMotionWork(const Catalog& catalog, const v1::EvaluateMotionRequest& request) {
  const auto& layers = request.motion().layers();
  return {layers.size(), request.times_size(), layers.empty() ? 0 : SkeletonJointsOf(catalog, layers[0].clip())};
}

Status EvaluateClip(const Catalog& catalog, const Limits& limits, const v1::EvaluateClipRequest& request,
                    v1::EvaluateClipResponse* response, ReplyEncoding encoding, CallProgress progress) {
  auto ref = catalog.FindClip(request.clip());
  if (!ref.ok()) return ref.status();
  ARMATURE_RETURN_IF_ERROR(ValidateTimes(AsSpan(request.times()), limits, "times"));
  const RequestWork work = EvaluateClipWork(catalog, request);
  ARMATURE_RETURN_IF_ERROR(ValidateRequestWork(work, limits, "EvaluateClip"));
  ARMATURE_RETURN_IF_ERROR(ValidateEnum(request.interpolation(), v1::Interpolation_descriptor(), "interpolation"));
  ARMATURE_RETURN_IF_ERROR(ValidateEnum(request.wrap(), v1::WrapMode_descriptor(), "wrap"));
  ARMATURE_RETURN_IF_ERROR(ValidateEnum(request.space(), v1::Space_descriptor(), "space"));
  const CompressedClip& clip = *ref->part->runtime;
  auto joints = ResolveJoints(*clip.skeleton, request.joints(), "joints");
  if (!joints.ok()) return joints.status();
  ARMATURE_RETURN_IF_ERROR(ValidatePosesReplySize(request.times_size(), joints->size(), limits, encoding,
                                                  "EvaluateClip",
                                                  "stream the poses (StreamClip: GET /v1/clips/{clip}:stream)"));

  const v1::Space space = request.space() == v1::WORLD ? v1::WORLD : v1::LOCAL;

  thread_local PoseWorkspace ws;  // reused across calls on this thread: no allocation per pose
  thread_local ClipSamplingContext context;
  ws.Resize(clip.skeleton->size());
  const CompressedClip& runtime = *ref->part->runtime;
  if (!context.Fits(runtime)) context.Resize(runtime);
  ClipSamplingJob job{&runtime, 0, FromProto(request.wrap()), &context, ws.local, FromProto(request.interpolation())};
  response->set_clip(ref->part->name);
  response->set_skeleton(ref->part->skeleton_name);
  response->set_space(space);
  for (int j : *joints) response->add_joints(j);
  response->mutable_times()->CopyFrom(request.times());
  response->mutable_poses()->Reserve(request.times_size());
  for (double t : request.times()) {
    job.time = t;
    ARMATURE_RETURN_IF_ERROR(job.Run());
    PackPose(*clip.skeleton, space, *joints, ws, response->add_poses());
    ARMATURE_RETURN_IF_ERROR(progress.Step(work.joints));
  }
  return Status::Ok();
}

Status EvaluateMotion(const Catalog& catalog, const Limits& limits, const v1::EvaluateMotionRequest& request,
                      v1::EvaluateMotionResponse* response, ReplyEncoding encoding, CallProgress progress) {
  ARMATURE_RETURN_IF_ERROR(ValidateTimes(AsSpan(request.times()), limits, "times"));
  ARMATURE_RETURN_IF_ERROR(ValidateEnum(request.space(), v1::Space_descriptor(), "space"));
  if (!request.has_motion()) return Status::InvalidArgument("motion: required (give at least one layer)");
  auto plan = BindMotionProto(catalog, request.motion(), limits, "motion");
  if (!plan.ok()) return plan.status();
  const RequestWork work = EvaluateMotionWork(catalog, request);
  ARMATURE_RETURN_IF_ERROR(ValidateRequestWork(work, limits, "EvaluateMotion"));
  const Skeleton& skeleton = *plan->skeleton;
  auto joints = ResolveJoints(skeleton, request.joints(), "joints");
  if (!joints.ok()) return joints.status();
  ARMATURE_RETURN_IF_ERROR(ValidatePosesReplySize(request.times_size(), joints->size(), limits, encoding,
                                                  "EvaluateMotion", "stream the poses (StreamClip with a motion)"));
  const v1::Space space = request.space() == v1::WORLD ? v1::WORLD : v1::LOCAL;
  const bool extract = plan->root_motion == RootMotion::kExtract;

  thread_local PoseWorkspace ws;
  thread_local MotionWorkspace motion_ws;
  ws.Resize(skeleton.size());
  motion_ws.Resize(*plan);
  response->set_skeleton(catalog.FindClip(request.motion().layers(0).clip())->part->skeleton_name);
  response->set_space(space);
  for (int j : *joints) response->add_joints(j);
  response->mutable_times()->CopyFrom(request.times());
  response->mutable_poses()->Reserve(request.times_size());
  for (double t : request.times()) {
    RootDelta delta;
    const BlendMotionJob job{&*plan, t, &motion_ws, ws.local, extract ? &delta : nullptr};
    ARMATURE_RETURN_IF_ERROR(job.Run());
    PackPose(skeleton, space, *joints, ws, response->add_poses());
    if (extract) {
      v1::Pose* root = response->add_root_motion();
      for (double v : delta.translation) root->add_translations(static_cast<float>(v));
      for (double v : {delta.rotation.w(), delta.rotation.x(), delta.rotation.y(), delta.rotation.z()})
        root->add_rotations(static_cast<float>(v));
    }
    ARMATURE_RETURN_IF_ERROR(progress.Step(work.layers * work.joints));
  }
  return Status::Ok();
}

Status ComputeFk(const Catalog& catalog, const v1::ComputeFkRequest& request, v1::ComputeFkResponse* response) {
  auto ref = catalog.FindSkeleton(request.skeleton());
  if (!ref.ok()) return ref.status();
  const Skeleton& skeleton = *ref->part->skeleton;
  if (request.pose().rotations().empty())
    return Status::InvalidArgument("pose.rotations: required (4 values per joint: w, x, y, z)");
  auto joints = ResolveJoints(skeleton, request.joints(), "joints");
  if (!joints.ok()) return joints.status();
  thread_local PoseWorkspace ws;
  ws.Resize(skeleton.size());
  ARMATURE_RETURN_IF_ERROR(
      PoseFromArrays(skeleton, AsSpan(request.pose().rotations()), AsSpan(request.pose().translations()), ws.local));
  response->set_skeleton(ref->part->name);
  for (int j : *joints) response->add_joints(j);
  PackPose(skeleton, v1::WORLD, *joints, ws, response->mutable_world());
  return Status::Ok();
}

}  // namespace armature::server
