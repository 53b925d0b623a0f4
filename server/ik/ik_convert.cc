#include "server/ik/ik_convert.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>
#include <optional>
#include <tuple>

#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/joint_map.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "server/rpc/request_validation.h"

namespace armature::server {
namespace {

using google::protobuf::RepeatedField;

std::string Indexed(const std::string& field, int i) { return field + "[" + std::to_string(i) + "]"; }

// Field names are built only on failure: `field` is a callable returning one.
template <class Field>
Status ReadVector3(const RepeatedField<double>& v, Field&& field, std::optional<Eigen::Vector3d>& out) {
  out.reset();
  if (v.empty()) return Status::Ok();
  if (v.size() != 3)
    return Status::InvalidArgument(field() + ": expected 3 values (x, y, z), got " + std::to_string(v.size()));
  const Eigen::Vector3d p(v[0], v[1], v[2]);
  if (!p.allFinite()) return Status::InvalidArgument(field() + ": not finite");
  out = p;
  return Status::Ok();
}

template <class Field>
Status ReadVector3Or(const RepeatedField<double>& v, Field&& field, const Eigen::Vector3d& fallback,
                     Eigen::Vector3d& out) {
  std::optional<Eigen::Vector3d> read;
  ARMATURE_RETURN_IF_ERROR(ReadVector3(v, field, read));
  out = read.value_or(fallback);
  return Status::Ok();
}

template <class Field>
Status ReadRotation(const RepeatedField<double>& v, Field&& field, std::optional<Eigen::Quaterniond>& out) {
  out.reset();
  if (v.empty()) return Status::Ok();
  if (v.size() != 4)
    return Status::InvalidArgument(field() + ": expected 4 values (w, x, y, z), got " + std::to_string(v.size()));
  const Eigen::Quaterniond q(v[0], v[1], v[2], v[3]);
  const double n = q.norm();
  if (!std::isfinite(n) || n < 1e-9) return Status::InvalidArgument(field() + ": not finite or a zero quaternion");
  out = q;
  return Status::Ok();
}

StatusOr<IkSolver> SolverFromProto(v1::IkSolver s) {
  switch (s) {
    case v1::IK_SOLVER_UNSPECIFIED:
    case v1::DLS: return IkSolver::kDls;
    case v1::TWO_BONE: return IkSolver::kTwoBone;
    case v1::CCD: return IkSolver::kCcd;
    case v1::FABRIK: return IkSolver::kFabrik;
    case v1::AIM: return IkSolver::kAim;
    default: return Status::InvalidArgument("solver: unknown value " + std::to_string(static_cast<int>(s)));
  }
}

v1::IkStop StopToProto(IkStop s) {
  switch (s) {
    case IkStop::kConverged: return v1::STOP_CONVERGED;
    case IkStop::kIterationCap: return v1::STOP_ITERATION_CAP;
    case IkStop::kStalled: return v1::STOP_STALLED;
    case IkStop::kDeadline: return v1::STOP_DEADLINE;
    case IkStop::kCancelled: return v1::STOP_CANCELLED;
    case IkStop::kDone: return v1::STOP_DONE;
  }
  return v1::IK_STOP_UNSPECIFIED;
}

Status EffectorFromProto(const v1::IkEffector& in, int i, IkEffector& out) {
  auto f = [i](const char* name) { return [i, name] { return Indexed("effectors", i) + "." + name; }; };
  out = IkEffector{};
  out.joint = in.joint();
  ARMATURE_RETURN_IF_ERROR(ReadVector3(in.target_position(), f("target_position"), out.target_position));
  ARMATURE_RETURN_IF_ERROR(ReadRotation(in.target_rotation(), f("target_rotation"), out.target_rotation));
  if (in.has_position_weight()) out.position_weight = in.position_weight();
  if (in.has_rotation_weight()) out.rotation_weight = in.rotation_weight();
  ARMATURE_RETURN_IF_ERROR(
      ReadVector3Or(in.local_offset(), f("local_offset"), Eigen::Vector3d::Zero(), out.local_offset));
  ARMATURE_RETURN_IF_ERROR(ReadVector3(in.pole(), f("pole"), out.pole));
  ARMATURE_RETURN_IF_ERROR(ReadVector3Or(in.aim_axis(), f("aim_axis"), Eigen::Vector3d::UnitZ(), out.aim_axis));
  ARMATURE_RETURN_IF_ERROR(ReadVector3Or(in.up_axis(), f("up_axis"), Eigen::Vector3d::UnitY(), out.up_axis));
  return ReadVector3(in.up_hint(), f("up_hint"), out.up_hint);
}

Status LimitFromProto(const v1::JointLimit& in, int i, JointLimit& out) {
  auto f = [i](const char* name) { return [i, name] { return Indexed("limits", i) + "." + name; }; };
  out = JointLimit{};
  out.joint = in.joint();
  const bool euler = in.kind() == v1::JointLimit::KIND_UNSPECIFIED || in.kind() == v1::JointLimit::EULER;
  if (!euler && in.kind() != v1::JointLimit::SWING_TWIST)
    return Status::InvalidArgument(f("kind")() + ": unknown value " + std::to_string(static_cast<int>(in.kind())));
  // A field of the other kind would be silently ignored: say so instead.
  auto only_for = [&](bool set, const char* name, const char* kind) {
    return set ? Status::InvalidArgument(f(name)() + ": only for " + kind + " limits") : Status::Ok();
  };
  if (euler) {
    out.kind = JointLimit::Kind::kEuler;
    ARMATURE_RETURN_IF_ERROR(only_for(!in.axis().empty(), "axis", "SWING_TWIST"));
    ARMATURE_RETURN_IF_ERROR(only_for(in.has_cone_deg(), "cone_deg", "SWING_TWIST"));
    ARMATURE_RETURN_IF_ERROR(only_for(in.has_twist_min_deg(), "twist_min_deg", "SWING_TWIST"));
    ARMATURE_RETURN_IF_ERROR(only_for(in.has_twist_max_deg(), "twist_max_deg", "SWING_TWIST"));
    auto order = ParseEulerOrder(in.order(), Indexed("limits", i) + ".order");
    if (!order.ok()) return order.status();
    out.order = *order;
    // Finiteness and min <= max are the engine's (ValidateJointLimit).
    for (auto [values, name, target] :
         {std::tuple{&in.min_deg(), "min_deg", &out.min_deg}, std::tuple{&in.max_deg(), "max_deg", &out.max_deg}}) {
      if (values->empty()) continue;
      if (values->size() != 3)
        return Status::InvalidArgument(f(name)() + ": expected 3 values (degrees, one per axis of `order`), got " +
                                       std::to_string(values->size()));
      *target = Eigen::Vector3d((*values)[0], (*values)[1], (*values)[2]);
    }
    return Status::Ok();
  }
  out.kind = JointLimit::Kind::kSwingTwist;
  ARMATURE_RETURN_IF_ERROR(only_for(!in.order().empty(), "order", "EULER"));
  ARMATURE_RETURN_IF_ERROR(only_for(!in.min_deg().empty(), "min_deg", "EULER"));
  ARMATURE_RETURN_IF_ERROR(only_for(!in.max_deg().empty(), "max_deg", "EULER"));
  ARMATURE_RETURN_IF_ERROR(ReadVector3Or(in.axis(), f("axis"), Eigen::Vector3d::UnitX(), out.axis));
  if (in.has_cone_deg()) out.cone_deg = in.cone_deg();
  if (in.has_twist_min_deg()) out.twist_min_deg = in.twist_min_deg();
  if (in.has_twist_max_deg()) out.twist_max_deg = in.twist_max_deg();
  return Status::Ok();
}

Status OptionsFromProto(const v1::IkOptions& in, const Limits& limits, IkOptions& out) {
  out = IkOptions{};
  // 0 = the engine's default, within the server's cap; negative is the engine's error.
  if (in.max_iterations() > limits.max_ik_iterations)
    return Status::ResourceExhausted("options.max_iterations: " + std::to_string(in.max_iterations()) +
                                     " is over the limit of " + std::to_string(limits.max_ik_iterations) +
                                     " (--max-ik-iterations)");
  out.max_iterations =
      in.max_iterations() != 0 ? in.max_iterations() : std::min(out.max_iterations, limits.max_ik_iterations);
  out.position_tolerance = in.position_tolerance();
  if (in.has_rotation_tolerance()) out.rotation_tolerance = in.rotation_tolerance();
  out.regularization = in.regularization();
  if (in.has_max_restarts()) out.max_restarts = in.max_restarts();
  if (in.seed() != 0) out.seed = in.seed();
  out.softness = in.softness();
  return Status::Ok();
}

Status StartFromClip(const Catalog& catalog, const v1::ClipTime& in, const NamedSkeleton& skeleton,
                     std::vector<Trs>& start) {
  auto clip = catalog.FindClip(in.clip());
  if (!clip.ok()) return clip.status().WithContext("from_clip.clip: ");
  // A clip of another skeleton plays by joint name (anim/joint_map.h).
  const Skeleton& sk = *skeleton.skeleton;
  std::vector<int> map;
  if (Status mapped = MapJointsByName(sk, *clip->part->runtime->skeleton, "'" + skeleton.name + "'", map); !mapped.ok())
    return Status::InvalidArgument("from_clip.clip: '" + clip->part->name + "' animates skeleton '" +
                                   clip->part->skeleton_name + "', which " + mapped.message());
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(in.time(), "from_clip.time"));
  if (in.time() < 0) return Status::InvalidArgument("from_clip.time: must not be negative");
  start.resize(sk.size());
  const CompressedClip& runtime = *clip->part->runtime;
  // On the clip's own skeleton as EvaluateClip samples it (the same locals, to the float).
  if (runtime.skeleton.get() == &sk)
    return ClipSamplingJob{&runtime, in.time(), FromProto(in.wrap()), nullptr, start, FromProto(in.interpolation())}
        .Run();
  ClipSamplingContext context(runtime);
  return ClipSamplingOntoJob{
      &runtime, map, &sk, in.time(), FromProto(in.wrap()), &context, start, FromProto(in.interpolation())}
      .Run();
}

// Which joints may carry the body (ik_body_root.h), from every clip of the skeleton.
std::vector<uint8_t> BodyRootCandidatesOf(const Catalog& catalog, const NamedSkeleton& skeleton) {
  std::vector<const CompressedClip*> clips;
  for (const auto& [name, ref] : catalog.clips)
    if (ref.part->skeleton_name == skeleton.name && ref.part->runtime->skeleton->size() == skeleton.skeleton->size())
      clips.push_back(ref.part->runtime.get());
  return BodyRootCandidates(*skeleton.skeleton, clips);
}

}  // namespace

Status ApiFieldNames(const Status& status) {
  const std::string& m = status.message();
  if (m.rfind("pose.", 0) == 0) return Status(status.code(), "start_" + m);
  // The engine's two root flags are the API's one free_root.
  for (const char* engine : {"free_root_rotation:", "free_root_translation:"})
    if (m.rfind(engine, 0) == 0) return Status(status.code(), "free_root:" + m.substr(std::string(engine).size()));
  return status;
}

// Σ over effectors of the joints in its chain (the joint and its ancestors,
// at most max_chain_depth of them when set) × iterations vs --max-ik-work.
static Status ValidateIkWork(const Skeleton& sk, const v1::SolveIkRequest& in, int iterations, const Limits& limits) {
  int64_t chain_joints = 0;
  for (const v1::IkEffector& e : in.effectors()) {
    int64_t depth = 0;
    for (int j = sk.Find(e.joint()); j >= 0; j = sk.parents[j]) ++depth;
    if (in.max_chain_depth() > 0) depth = std::min<int64_t>(depth, in.max_chain_depth());
    chain_joints += depth;
  }
  const int64_t work = chain_joints * std::max(iterations, 1);
  if (work <= limits.max_ik_work) return Status::Ok();
  return Status::ResourceExhausted("effectors, options.max_iterations: " + std::to_string(chain_joints) +
                                   " chain joints x " + std::to_string(iterations) +
                                   " iterations = " + std::to_string(work) + " is over the limit of " +
                                   std::to_string(limits.max_ik_work) + " (--max-ik-work); ask for fewer");
}

Status IkCallFromProto(const Catalog& catalog, const Limits& limits, const v1::SolveIkRequest& in, IkCall& call) {
  auto skeleton = catalog.FindSkeleton(in.skeleton());
  if (!skeleton.ok()) return skeleton.status();
  call.skeleton = std::move(*skeleton);
  const Skeleton& sk = *call.skeleton.part->skeleton;
  IkRequest& r = call.request;

  switch (in.start_case()) {
    case v1::SolveIkRequest::kStartPose:
      call.start.resize(sk.size());
      ARMATURE_RETURN_IF_ERROR(ApiFieldNames(
          PoseFromArrays(sk, AsSpan(in.start_pose().rotations()), AsSpan(in.start_pose().translations()), call.start)));
      break;
    case v1::SolveIkRequest::kFromClip:
      ARMATURE_RETURN_IF_ERROR(StartFromClip(catalog, in.from_clip(), *call.skeleton.part, call.start));
      break;
    default: call.start.clear();
  }
  r.start_pose = call.start;

  auto solver = SolverFromProto(in.solver());
  if (!solver.ok()) return solver.status();
  r.solver = *solver;
  // Checked before anything is built per effector: a solve's cost grows with
  // effectors × chain joints × iterations (3,000 effectors ran for 52 s).
  if (in.effectors_size() > limits.max_ik_effectors)
    return Status::ResourceExhausted("effectors: " + std::to_string(in.effectors_size()) +
                                     " effectors are over the limit of " + std::to_string(limits.max_ik_effectors) +
                                     " (--max-ik-effectors)");
  ARMATURE_RETURN_IF_ERROR(OptionsFromProto(in.options(), limits, r.options));
  ARMATURE_RETURN_IF_ERROR(ValidateIkWork(sk, in, r.options.max_iterations, limits));
  r.effectors.resize(in.effectors_size());
  for (int i = 0; i < in.effectors_size(); ++i)
    ARMATURE_RETURN_IF_ERROR(EffectorFromProto(in.effectors(i), i, r.effectors[i]));
  r.limits.resize(in.limits_size());
  for (int i = 0; i < in.limits_size(); ++i) ARMATURE_RETURN_IF_ERROR(LimitFromProto(in.limits(i), i, r.limits[i]));
  r.root = in.root();
  r.max_chain_depth = in.max_chain_depth();
  r.free_joints.assign(in.free_joints().begin(), in.free_joints().end());
  ARMATURE_RETURN_IF_ERROR(ValidateEnum(in.free_root(), v1::FreeRoot_descriptor(), "free_root"));
  call.body_root_candidates = BodyRootCandidatesOf(catalog, *call.skeleton.part);
  r.body_root_candidates = call.body_root_candidates;
  r.free_root_rotation = in.free_root() == v1::ROOT_ROTATION || in.free_root() == v1::ROOT_ROTATION_AND_TRANSLATION;
  r.free_root_translation =
      in.free_root() == v1::ROOT_TRANSLATION || in.free_root() == v1::ROOT_ROTATION_AND_TRANSLATION;
  return Status::Ok();
}

Status ApplyTargetUpdates(const google::protobuf::RepeatedPtrField<v1::IkTargetUpdate>& updates, IkRequest& request) {
  for (int i = 0; i < updates.size(); ++i) {
    const v1::IkTargetUpdate& u = updates[i];
    auto f = [i](const char* name) { return [i, name] { return Indexed("targets", i) + "." + name; }; };
    const int n = static_cast<int>(request.effectors.size());
    if (u.effector() < 0 || u.effector() >= n)
      return Status::InvalidArgument(f("effector")() + ": " + std::to_string(u.effector()) +
                                     " is out of range (the session has " + std::to_string(n) + " effector" +
                                     (n == 1 ? "" : "s") + ")");
    IkEffector& e = request.effectors[u.effector()];
    std::optional<Eigen::Vector3d> v;
    std::optional<Eigen::Quaterniond> q;
    ARMATURE_RETURN_IF_ERROR(ReadVector3(u.target_position(), f("target_position"), v));
    if (v) e.target_position = v;
    ARMATURE_RETURN_IF_ERROR(ReadRotation(u.target_rotation(), f("target_rotation"), q));
    if (q) e.target_rotation = q;
    ARMATURE_RETURN_IF_ERROR(ReadVector3(u.pole(), f("pole"), v));
    if (v) e.pole = v;
  }
  return Status::Ok();
}

void IkResponseToProto(const IkCall& call, const IkResult& result, PoseWorkspace& ws, v1::SolveIkResponse* out) {
  const Skeleton& sk = *call.skeleton.part->skeleton;
  const int n = static_cast<int>(sk.size());
  out->Clear();
  out->set_skeleton(call.skeleton.part->name);
  auto* joints = out->mutable_joints();
  joints->Resize(n, 0);
  std::iota(joints->begin(), joints->end(), 0);
  ws.Resize(sk.size());
  std::copy(result.pose.begin(), result.pose.end(), ws.local.begin());
  const std::span<const int> all(joints->data(), joints->size());
  PackPose(sk, v1::LOCAL, all, ws, out->mutable_local());
  PackPose(sk, v1::WORLD, all, ws, out->mutable_world());
  for (size_t i = 0; i < result.residuals.size(); ++i) {
    const IkEffectorResidual& r = result.residuals[i];
    v1::IkResidual* p = out->add_residuals();
    p->set_joint(call.request.effectors[i].joint);
    p->set_position_error(r.position_error);
    p->set_rotation_error(r.rotation_error);
    p->set_reached(r.reached);
    if (r.body_root >= 0) p->set_body_root(sk.names[static_cast<size_t>(r.body_root)]);
  }
  out->set_converged(result.converged);
  out->set_stop(StopToProto(result.stop));
  out->set_iterations(result.iterations);
  out->set_restarts(result.restarts);
}

}  // namespace armature::server
