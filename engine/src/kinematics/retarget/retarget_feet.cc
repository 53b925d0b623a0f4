#include "retarget_feet.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "armature/engine/kinematics/ik.h"

namespace armature {
namespace {

constexpr const char* kSide[2] = {"left", "right"};

}  // namespace

Status PlanFeet(const Skeleton& target, const BodyParts& parts, std::span<const Eigen::Affine3d> rest_world,
                FeetPlan& plan) {
  double total = 0;
  for (size_t side = 0; side < 2; ++side) {
    const LimbJoints& leg = parts.legs[side];
    const std::string which = std::string("feet: the target's ") + kSide[side] + " leg";
    if (leg.upper < 0 || leg.lower < 0 || leg.end < 0)
      return Status::InvalidArgument(which + " has no hip–knee–ankle chain (" +
                                     (leg.upper < 0   ? "no thigh"
                                      : leg.lower < 0 ? "no shin"
                                                      : "no foot") +
                                     " joint found); map the leg's joints explicitly or retarget without feet");
    if (target.parents[static_cast<size_t>(leg.lower)] != leg.upper)
      return Status::InvalidArgument(which + " has no hip–knee–ankle chain: the shin '" +
                                     target.names[static_cast<size_t>(leg.lower)] + "' does not hang from the thigh '" +
                                     target.names[static_cast<size_t>(leg.upper)] + "'");
    FeetPlan::Leg& out = plan.legs[side];
    out.hip = leg.upper;
    out.knee = leg.lower;
    out.foot = leg.end;
    if (target.parents[static_cast<size_t>(leg.end)] == leg.lower) {
      out.effector = leg.end;
    } else {
      // The foot hangs elsewhere (an IK rig's control bone): reach with a child of the
      // shin, offset to the foot's rest position.
      for (size_t j = 0; j < target.size() && out.effector < 0; ++j)
        if (target.parents[j] == leg.lower) out.effector = static_cast<int>(j);
      if (out.effector < 0)
        return Status::InvalidArgument(which + " has no hip–knee–ankle chain: the foot '" +
                                       target.names[static_cast<size_t>(leg.end)] + "' does not hang from the shin '" +
                                       target.names[static_cast<size_t>(leg.lower)] +
                                       "', which has no child to reach with");
      out.offset = rest_world[static_cast<size_t>(out.effector)].inverse() *
                   rest_world[static_cast<size_t>(leg.end)].translation();
    }
    total += (rest_world[static_cast<size_t>(leg.lower)].translation() -
              rest_world[static_cast<size_t>(leg.upper)].translation())
                 .norm() +
             (rest_world[static_cast<size_t>(leg.end)].translation() -
              rest_world[static_cast<size_t>(leg.lower)].translation())
                 .norm();
    IkEffector effector;
    effector.joint = target.names[static_cast<size_t>(out.effector)];
    effector.local_offset = out.offset;
    effector.target_position = Eigen::Vector3d::Zero();
    out.request.solver = IkSolver::kTwoBone;
    out.request.effectors = {effector};
  }
  plan.leg_length = total / 2;
  return Status::Ok();
}

Status FindPlantedFeet(std::span<const double> times, const BodyParts& source_parts,
                       const std::function<Status(double)>& sample, const std::vector<Eigen::Affine3d>& source_world,
                       std::vector<FootPins>& pins) {
  const size_t n = times.size();
  pins.assign(2, FootPins{});
  for (size_t side = 0; side < 2; ++side) {
    const LimbJoints& leg = source_parts.legs[side];
    if (leg.upper < 0 || leg.lower < 0 || leg.end < 0)
      return Status::InvalidArgument(std::string("feet: the source clip's ") + kSide[side] +
                                     " leg has no hip–knee–ankle chain to read its contacts from");
  }
  std::array<std::vector<Eigen::Vector3d>, 2> ankle;
  double leg_length = 0;
  for (size_t i = 0; i < n; ++i) {
    ARMATURE_RETURN_IF_ERROR(sample(times[i]));
    for (size_t side = 0; side < 2; ++side) {
      const LimbJoints& leg = source_parts.legs[side];
      ankle[side].push_back(source_world[static_cast<size_t>(leg.end)].translation());
      if (i == 0)
        leg_length += 0.5 * ((source_world[static_cast<size_t>(leg.lower)].translation() -
                              source_world[static_cast<size_t>(leg.upper)].translation())
                                 .norm() +
                             (source_world[static_cast<size_t>(leg.end)].translation() -
                              source_world[static_cast<size_t>(leg.lower)].translation())
                                 .norm());
    }
  }
  if (n < 3 || leg_length <= 0) {
    for (FootPins& p : pins) p.stretch.assign(n, -1);
    return Status::Ok();
  }
  for (size_t side = 0; side < 2; ++side) {
    const std::vector<Eigen::Vector3d>& a = ankle[side];
    double ground = a[0].y();
    for (const auto& p : a) ground = std::min(ground, p.y());
    std::vector<bool> planted(n);
    for (size_t i = 0; i < n; ++i) {
      const size_t lo = i == 0 ? 0 : i - 1, hi = i + 1 < n ? i + 1 : n - 1;
      const double speed = (a[hi] - a[lo]).norm() / std::max(times[hi] - times[lo], 1e-9);
      planted[i] = a[i].y() - ground < 0.10 * leg_length && speed < 0.30 * leg_length;
    }
    // Short gaps where the foot barely moved (a jitter in the speed) are not lifts.
    for (size_t i = 1; i < n;) {
      if (planted[i] || !planted[i - 1]) {
        ++i;
        continue;
      }
      size_t next = i;
      while (next < n && !planted[next]) ++next;
      if (next < n && times[next] - times[i - 1] < 0.1 && (a[next] - a[i - 1]).norm() < 0.05 * leg_length)
        for (size_t k = i; k < next; ++k) planted[k] = true;
      i = next;
    }
    FootPins& out = pins[side];
    out.stretch.assign(n, -1);
    int stretches = 0;
    for (size_t i = 0; i < n;) {
      if (!planted[i]) {
        ++i;
        continue;
      }
      size_t end = i;
      while (end < n && planted[end]) ++end;
      if (end - i >= 3) {
        for (size_t k = i; k < end; ++k) out.stretch[k] = stretches;
        ++stretches;
      }
      i = end;
    }
  }
  return Status::Ok();
}

void SetPins(const std::vector<std::vector<Eigen::Vector3d>>& natural, std::vector<FootPins>& pins) {
  for (size_t side = 0; side < 2; ++side) {
    FootPins& p = pins[side];
    int count = 0;
    for (int s : p.stretch) count = std::max(count, s + 1);
    p.pin.assign(static_cast<size_t>(count), Eigen::Vector3d::Zero());
    std::vector<int> frames(static_cast<size_t>(count), 0);
    for (size_t i = 0; i < p.stretch.size(); ++i) {
      if (p.stretch[i] < 0) continue;
      p.pin[static_cast<size_t>(p.stretch[i])] += natural[side][i];
      ++frames[static_cast<size_t>(p.stretch[i])];
    }
    for (size_t k = 0; k < p.pin.size(); ++k) p.pin[k] /= std::max(frames[k], 1);
  }
}

Status PinFeet(const Skeleton& target, FeetPlan& plan, std::vector<FootPins>& pins, size_t frame, int moved_root,
               std::vector<Trs>& local, std::vector<Eigen::Affine3d>& world,
               const std::vector<Eigen::Quaterniond>& rotation, IkWorkspace& workspace, IkResult& result) {
  // Lower the hips as far as the leg that is shortest of its pin needs.
  double lower = 0;
  for (size_t side = 0; side < 2 && moved_root >= 0; ++side) {
    const FootPins& p = pins[side];
    const int stretch = p.stretch[frame];
    if (stretch < 0) continue;
    const FeetPlan::Leg& leg = plan.legs[side];
    const Eigen::Vector3d hip = world[static_cast<size_t>(leg.hip)].translation();
    const Eigen::Vector3d knee = world[static_cast<size_t>(leg.knee)].translation();
    const double reach =
        0.999 * ((knee - hip).norm() + (world[static_cast<size_t>(leg.effector)] * leg.offset - knee).norm());
    const Eigen::Vector3d v = hip - p.pin[static_cast<size_t>(stretch)];
    const double horizontal2 = v.x() * v.x() + v.z() * v.z();
    if (v.squaredNorm() <= reach * reach || horizontal2 >= reach * reach) continue;
    lower = std::max(lower, v.y() - std::sqrt(reach * reach - horizontal2));
  }
  if (lower > 0) {
    local[static_cast<size_t>(moved_root)].translation.y() -= lower;
    for (auto& w : world) w.translation().y() -= lower;  // the hips' and knees' are all that is read below
  }
  for (size_t side = 0; side < 2; ++side) {
    FootPins& pins_of_leg = pins[side];
    const int stretch = pins_of_leg.stretch[frame];
    if (stretch < 0) continue;
    FeetPlan::Leg& leg = plan.legs[side];
    leg.request.start_pose = local;
    leg.request.effectors[0].target_position = pins_of_leg.pin[static_cast<size_t>(stretch)];
    ARMATURE_RETURN_IF_ERROR(SolveIk(target, leg.request, workspace, result));
    const Eigen::Quaterniond foot_world = rotation[static_cast<size_t>(leg.foot)];
    local[static_cast<size_t>(leg.hip)].rotation = result.pose[static_cast<size_t>(leg.hip)].rotation;
    local[static_cast<size_t>(leg.knee)].rotation = result.pose[static_cast<size_t>(leg.knee)].rotation;
    if (leg.effector == leg.foot) {
      const int hp = target.parents[static_cast<size_t>(leg.hip)];
      const Eigen::Quaterniond knee_world =
          (hp < 0 ? Eigen::Quaterniond::Identity() : rotation[static_cast<size_t>(hp)]) *
          local[static_cast<size_t>(leg.hip)].rotation * local[static_cast<size_t>(leg.knee)].rotation;
      local[static_cast<size_t>(leg.foot)].rotation = (knee_world.conjugate() * foot_world).normalized();
    }
  }
  return Status::Ok();
}

}  // namespace armature
