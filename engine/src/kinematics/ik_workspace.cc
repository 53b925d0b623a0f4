#include "armature/engine/kinematics/ik_workspace.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "armature/base/closest_name.h"
#include "armature/engine/kinematics/ik_body_root.h"
#include "armature/engine/kinematics/joint_limits.h"
#include "ik_internal.h"

namespace armature {
namespace {

std::string Indexed(const char* field, size_t i) { return std::string(field) + "[" + std::to_string(i) + "]"; }

bool Finite(double v) { return std::isfinite(v); }

// The joint named `name`, or INVALID_ARGUMENT "<field()>: unknown joint".
// Lookups are numbered in request order and each remembers its answer in
// ws.name_hints: a client repeating a request shape costs one string
// compare per name instead of a scan.
template <class Field>
StatusOr<int> Resolve(const Skeleton& skeleton, IkWorkspace& ws, const std::string& name, Field&& field) {
  const size_t slot = ws.name_lookups++;
  if (slot >= ws.name_hints.size()) ws.name_hints.resize(slot + 1, -1);
  int& hint = ws.name_hints[slot];
  if (hint >= 0 && hint < static_cast<int>(skeleton.size()) && skeleton.names[hint] == name) return hint;
  hint = skeleton.Find(name);
  if (hint < 0) return Status::InvalidArgument(field() + ": " + UnknownJoint(name, skeleton.names));
  return hint;
}

const char* SolverName(IkSolver s) {
  switch (s) {
    case IkSolver::kDls: return "dls";
    case IkSolver::kTwoBone: return "two-bone";
    case IkSolver::kCcd: return "ccd";
    case IkSolver::kFabrik: return "fabrik";
    case IkSolver::kAim: return "aim";
  }
  return "?";
}

Status CheckOptions(const IkOptions& o) {
  if (o.max_iterations < 0) return Status::InvalidArgument("options.max_iterations: negative");
  if (!Finite(o.position_tolerance) || o.position_tolerance < 0)
    return Status::InvalidArgument("options.position_tolerance: negative or not finite");
  if (!Finite(o.rotation_tolerance) || o.rotation_tolerance < 0)
    return Status::InvalidArgument("options.rotation_tolerance: negative or not finite");
  if (!Finite(o.regularization) || o.regularization < 0)
    return Status::InvalidArgument("options.regularization: negative or not finite");
  if (o.max_restarts < 0) return Status::InvalidArgument("options.max_restarts: negative");
  if (!Finite(o.softness) || o.softness < 0 || o.softness >= 1)
    return Status::InvalidArgument("options.softness: must be in [0, 1)");
  return Status::Ok();
}

Status CheckStartPose(const Skeleton& skeleton, std::span<const Trs> pose) {
  if (pose.empty()) return Status::Ok();
  if (pose.size() != skeleton.size())
    return Status::InvalidArgument("start_pose: expected " + std::to_string(skeleton.size()) + " joints, got " +
                                   std::to_string(pose.size()));
  for (size_t i = 0; i < pose.size(); ++i) {
    const Trs& t = pose[i];
    const double n = t.rotation.norm();
    if (!t.translation.allFinite() || !t.scale.allFinite() || !Finite(n) || n < 1e-9)
      return Status::InvalidArgument(Indexed("start_pose", i) + " ('" + skeleton.names[i] +
                                     "'): not finite or a zero quaternion");
  }
  return Status::Ok();
}

Status ResolveEffector(const Skeleton& skeleton, const IkRequest& request, size_t i, IkWorkspace& ws) {
  IkWorkspace::Effector& out = ws.effectors[i];
  const IkEffector& in = request.effectors[i];
  // Field names are built only on failure (this runs per request).
  auto fail = [&](const std::string& what) { return Status::InvalidArgument(Indexed("effectors", i) + what); };
  ARMATURE_ASSIGN_OR_RETURN(const int joint,
                            Resolve(skeleton, ws, in.joint, [&] { return Indexed("effectors", i) + ".joint"; }));
  out = IkWorkspace::Effector{};
  out.joint = joint;
  if (!in.local_offset.allFinite()) return fail(".local_offset: not finite");
  out.offset = in.local_offset;
  if (in.target_position) {
    if (!in.target_position->allFinite()) return fail(".target_position: not finite");
    out.has_position = true;
    out.target_position = *in.target_position;
  }
  if (in.target_rotation) {
    const double n = in.target_rotation->norm();
    if (!Finite(n) || n < 1e-9) return fail(".target_rotation: not finite or a zero quaternion");
    out.has_rotation = true;
    out.target_rotation = Eigen::Quaterniond(in.target_rotation->coeffs() / n);
  }
  if (!out.has_position && !out.has_rotation) return fail(": needs a target_position or a target_rotation");
  if (!Finite(in.position_weight) || in.position_weight < 0) return fail(".position_weight: negative or not finite");
  if (!Finite(in.rotation_weight) || in.rotation_weight < 0) return fail(".rotation_weight: negative or not finite");
  out.position_weight = in.position_weight;
  out.rotation_weight = in.rotation_weight;
  if (in.pole && !in.pole->allFinite()) return fail(".pole: not finite");

  const IkSolver solver = request.solver;
  if (solver != IkSolver::kDls && !out.has_position)
    return fail(std::string(".target_position: required by the ") + SolverName(solver) + " solver");
  if (solver == IkSolver::kAim) {
    if (out.has_rotation) return fail(".target_rotation: not used by the aim solver");
    if (!in.local_offset.isZero()) return fail(".local_offset: aim turns about the joint's origin; must be zero");
    if (!in.aim_axis.allFinite() || in.aim_axis.norm() < 1e-12) return fail(".aim_axis: zero length or not finite");
    if (in.up_hint) {
      if (!in.up_hint->allFinite() || in.up_hint->norm() < 1e-12) return fail(".up_hint: zero length or not finite");
      if (!in.up_axis.allFinite() || in.up_axis.norm() < 1e-12) return fail(".up_axis: zero length or not finite");
      if (in.up_axis.normalized().cross(in.aim_axis.normalized()).norm() < 1e-6)
        return fail(".up_axis: parallel to aim_axis");
    }
  }
  if (solver == IkSolver::kTwoBone) {
    const int mid = skeleton.parents[out.joint];
    if (mid < 0 || skeleton.parents[mid] < 0)
      return fail(".joint: two-bone needs a parent and a grandparent of '" + in.joint + "'");
  }
  return Status::Ok();
}

Status ResolveLimits(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws) {
  ws.limit_of.assign(skeleton.size(), -1);
  for (size_t i = 0; i < request.limits.size(); ++i) {
    // The field name is only built on failure: this runs per request.
    ARMATURE_ASSIGN_OR_RETURN(const int joint, Resolve(skeleton, ws, request.limits[i].joint,
                                                       [&] { return Indexed("limits", i) + ".joint"; }));
    if (ws.limit_of[joint] >= 0)
      return Status::InvalidArgument(Indexed("limits", i) + ".joint: '" + request.limits[i].joint +
                                     "' is already limited by " + Indexed("limits", ws.limit_of[joint]));
    const Status valid = ValidateJointLimit(request.limits[i], "");
    if (!valid.ok()) return valid.WithContext(Indexed("limits", i));
    ws.limit_of[joint] = static_cast<int>(i);
  }
  return Status::Ok();
}

bool IsAncestorOrSelf(const Skeleton& skeleton, int ancestor, int joint) {
  for (int j = joint; j >= 0; j = skeleton.parents[j])
    if (j == ancestor) return true;
  return false;
}

// Marks free joints (mark bit 1) from the explicit list or the effector paths.
Status MarkFreeJoints(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws) {
  if (!request.free_joints.empty()) {
    if (!request.root.empty() || request.max_chain_depth != 0)
      return Status::InvalidArgument("free_joints: not combined with root or max_chain_depth");
    for (size_t i = 0; i < request.free_joints.size(); ++i) {
      ARMATURE_ASSIGN_OR_RETURN(
          const int j, Resolve(skeleton, ws, request.free_joints[i], [&] { return Indexed("free_joints", i); }));
      ws.mark[j] |= 1;
    }
    return Status::Ok();
  }
  if (request.max_chain_depth < 0) return Status::InvalidArgument("max_chain_depth: negative");
  int root = -1;
  if (!request.root.empty()) {
    ARMATURE_ASSIGN_OR_RETURN(const int r, Resolve(skeleton, ws, request.root, [] { return std::string("root"); }));
    root = r;
  }
  for (size_t i = 0; i < ws.effectors.size(); ++i) {
    const IkWorkspace::Effector& e = ws.effectors[i];
    if (root >= 0 && !IsAncestorOrSelf(skeleton, root, e.joint))
      return Status::InvalidArgument("root: '" + request.root + "' is not an ancestor of " + Indexed("effectors", i) +
                                     ".joint '" + skeleton.names[e.joint] + "'");
    const bool own_rotation_matters = e.has_rotation || !e.offset.isZero();
    int depth = 0;
    const int stop = root >= 0 ? root : e.body_root;
    // The body root is never on a path: free_root_rotation adds it below.
    for (int j = e.joint; j >= 0 && j != stop && skeleton.parents[j] >= 0; j = skeleton.parents[j]) {
      if (j == e.joint && !own_rotation_matters) continue;
      if (request.max_chain_depth > 0 && depth == request.max_chain_depth) break;
      ws.mark[j] |= 1;
      ++depth;
    }
  }
  return Status::Ok();
}

// free_root_rotation: the body root above each effector turns too, in
// addition to the paths or the explicit list.
void MarkFreeRoots(const IkRequest& request, IkWorkspace& ws) {
  if (!request.free_root_rotation) return;
  for (const IkWorkspace::Effector& e : ws.effectors)
    if (e.body_root != e.joint || e.has_rotation || !e.offset.isZero()) ws.mark[e.body_root] |= 1;
}

// Paths, translated roots, the update list and chain lengths, from the marks.
Status BuildChains(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws) {
  const int n = static_cast<int>(skeleton.size());
  ws.free_joints.clear();
  ws.translated_roots.clear();
  ws.paths.clear();
  ws.update.clear();
  // Bit 2: leads to an effector. Bit 4: translated root. Bit 8: moves with a free joint.
  for (const IkWorkspace::Effector& e : ws.effectors) {
    for (int j = e.joint; j >= 0; j = skeleton.parents[j]) ws.mark[j] |= 2;
    if (request.free_root_translation) ws.mark[e.body_root] |= 4;
  }
  for (int j = 0; j < n; ++j) {
    if (ws.mark[j] & 1) ws.free_joints.push_back(j);
    if (ws.mark[j] & 4) ws.translated_roots.push_back(j);
    const int p = skeleton.parents[j];
    if ((ws.mark[j] & 2) && ((ws.mark[j] & 5) || (p >= 0 && (ws.mark[p] & 8)))) {
      ws.mark[j] |= 8;
      ws.update.push_back(j);
    }
  }
  // The whole path to each effector is needed once; afterwards only `update`.
  for (int j = 0; j < n; ++j)
    if (ws.mark[j] & 2) ik_internal::UpdateWorldOf(skeleton, ws, j);

  double longest = 0;
  bool any_position = false;
  for (size_t i = 0; i < ws.effectors.size(); ++i) {
    IkWorkspace::Effector& e = ws.effectors[i];
    e.path_begin = static_cast<int>(ws.paths.size());
    int top = -1;
    for (int j = e.joint; j >= 0; j = skeleton.parents[j]) {
      if (ws.mark[j] & 1) ws.paths.push_back(j), top = j;
      if (ws.mark[j] & 4) e.translated_root = j, top = j;
    }
    e.path_end = static_cast<int>(ws.paths.size());
    auto f = [&] { return Indexed("effectors", i) + ".joint"; };
    if (top < 0)
      return Status::InvalidArgument(f() + ": no free joint moves '" + skeleton.names[e.joint] +
                                     "' (check root, max_chain_depth, free_joints, free_root)");
    if (!e.has_position) continue;
    any_position = true;
    double length = (ik_internal::EffectorPoint(ws, e) - ws.world_position[e.joint]).norm();
    for (int j = e.joint; j != top; j = skeleton.parents[j])
      length += (ws.world_position[j] - ws.world_position[skeleton.parents[j]]).norm();
    if (length < 1e-12 && e.translated_root < 0)
      return Status::InvalidArgument(f() + ": zero-length chain: the free joints above '" + skeleton.names[e.joint] +
                                     "' coincide with the effector point");
    longest = std::max(longest, length);
  }
  ws.chain_length = any_position && longest > 0 ? longest : 1.0;
  return Status::Ok();
}

Status CheckTwoBone(const Skeleton& skeleton, const IkWorkspace& ws) {
  for (size_t i = 0; i < ws.effectors.size(); ++i) {
    const IkWorkspace::Effector& e = ws.effectors[i];
    const int mid = skeleton.parents[e.joint], upper = skeleton.parents[mid];
    auto f = [&] { return Indexed("effectors", i) + ".joint"; };
    const double l1 = (ws.world_position[mid] - ws.world_position[upper]).norm();
    const double l2 = (ik_internal::EffectorPoint(ws, e) - ws.world_position[mid]).norm();
    if (l1 < 1e-12 || l2 < 1e-12)
      return Status::InvalidArgument(f() + ": zero-length two-bone chain: bone '" +
                                     skeleton.names[l1 < 1e-12 ? upper : mid] + "' has no length");
    for (int j : {upper, mid, e.has_rotation ? e.joint : -1})
      if (j >= 0 && ws.limit_of[j] >= 0)
        return Status::InvalidArgument(Indexed("limits", ws.limit_of[j]) +
                                       ".joint: the two-bone solver does not "
                                       "apply limits ('" +
                                       skeleton.names[j] + "' is in " + Indexed("effectors", i) +
                                       "'s chain); use dls, ccd or fabrik");
  }
  return Status::Ok();
}

Status CheckAim(const Skeleton& skeleton, const IkWorkspace& ws) {
  for (size_t i = 0; i < ws.effectors.size(); ++i) {
    const IkWorkspace::Effector& e = ws.effectors[i];
    if ((e.target_position - ws.world_position[e.joint]).norm() < 1e-12)
      return Status::InvalidArgument(Indexed("effectors", i) + ".target_position: at the origin of '" +
                                     skeleton.names[e.joint] + "'; nothing to aim at");
  }
  return Status::Ok();
}

}  // namespace

Status PrepareIkWorkspace(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws) {
  const size_t n = skeleton.size();
  if (static_cast<int>(request.solver) > static_cast<int>(IkSolver::kAim))
    return Status::InvalidArgument("solver: unknown value " + std::to_string(static_cast<int>(request.solver)));
  ARMATURE_RETURN_IF_ERROR(CheckOptions(request.options));
  ws.name_lookups = 0;
  ARMATURE_RETURN_IF_ERROR(CheckStartPose(skeleton, request.start_pose));
  ARMATURE_RETURN_IF_ERROR(ResolveLimits(skeleton, request, ws));
  if (request.effectors.empty()) return Status::InvalidArgument("effectors: empty");
  const bool single_chain = request.solver == IkSolver::kCcd || request.solver == IkSolver::kFabrik;
  if (single_chain && request.effectors.size() != 1)
    return Status::InvalidArgument(std::string("effectors: the ") + SolverName(request.solver) +
                                   " solver takes one effector, got " + std::to_string(request.effectors.size()));
  if (request.free_root_translation && request.solver != IkSolver::kDls)
    return Status::InvalidArgument("free_root_translation: only the dls solver translates the root");
  if (request.free_root_rotation && (request.solver == IkSolver::kTwoBone || request.solver == IkSolver::kAim))
    return Status::InvalidArgument(std::string("free_root_rotation: the ") + SolverName(request.solver) +
                                   " solver turns fixed joints; use dls, ccd or fabrik");
  ws.effectors.resize(request.effectors.size());
  for (size_t i = 0; i < request.effectors.size(); ++i) {
    ARMATURE_RETURN_IF_ERROR(ResolveEffector(skeleton, request, i, ws));
    ws.effectors[i].body_root = BodyRootAbove(skeleton, ws.effectors[i].joint, request.body_root_candidates);
  }

  if (request.start_pose.empty()) {
    ws.local.assign(skeleton.rest.begin(), skeleton.rest.end());
  } else {
    ws.local.assign(request.start_pose.begin(), request.start_pose.end());
    for (Trs& t : ws.local) t.rotation.normalize();
  }
  ws.world_linear.resize(n);
  ws.world_rotation.resize(n);
  ws.world_position.resize(n);
  ws.mark.assign(n, 0);
  if (request.solver == IkSolver::kTwoBone || request.solver == IkSolver::kAim) {
    // One-shot solvers move fixed joints; only the effectors' paths are needed.
    for (const IkWorkspace::Effector& e : ws.effectors)
      for (int j = e.joint; j >= 0; j = skeleton.parents[j]) ws.mark[j] |= 2;
    ws.update.clear();
    for (size_t j = 0; j < n; ++j)
      if (ws.mark[j] & 2) ws.update.push_back(static_cast<int>(j));
    ik_internal::UpdateWorld(skeleton, ws, ws.update);
    double longest = 0;
    if (request.solver == IkSolver::kTwoBone)
      for (const IkWorkspace::Effector& e : ws.effectors) {
        const int mid = skeleton.parents[e.joint];
        longest = std::max(longest, (ws.world_position[mid] - ws.world_position[skeleton.parents[mid]]).norm() +
                                        (ik_internal::EffectorPoint(ws, e) - ws.world_position[mid]).norm());
      }
    ws.chain_length = longest > 0 ? longest : 1.0;
    ARMATURE_RETURN_IF_ERROR(request.solver == IkSolver::kTwoBone ? CheckTwoBone(skeleton, ws)
                                                                  : CheckAim(skeleton, ws));
  } else {
    ARMATURE_RETURN_IF_ERROR(MarkFreeJoints(skeleton, request, ws));
    MarkFreeRoots(request, ws);
    ARMATURE_RETURN_IF_ERROR(BuildChains(skeleton, request, ws));
  }
  ws.position_tolerance =
      request.options.position_tolerance > 0 ? request.options.position_tolerance : 1e-4 * ws.chain_length;
  ws.random_state = request.options.seed;
  return Status::Ok();
}

}  // namespace armature
