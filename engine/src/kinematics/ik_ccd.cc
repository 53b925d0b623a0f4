#include "armature/engine/kinematics/ik_ccd.h"

#include "ik_internal.h"

namespace armature {

void SolveCcd(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, IkResult& result) {
  const IkWorkspace::Effector& e = ws.effectors[0];
  ik_internal::InterruptPoll poll(request, 256);  // a joint's turn is cheap here
  ik_internal::SweepUntilReached(skeleton, request, ws, result, [&]() -> std::optional<IkStop> {
    // Effector side first; each turn moves the effector point, whose new
    // place follows from the rotation actually applied (limits included).
    Eigen::Vector3d point = ik_internal::EffectorPoint(ws, e);
    for (int i = e.path_begin; i < e.path_end; ++i) {
      const int joint = ws.paths[i];
      const Eigen::Vector3d origin = ws.world_position[joint];
      const Eigen::Quaterniond turn =
          ik_internal::TurnJointTowards(skeleton, request, ws, joint, point, e.target_position);
      point = origin + turn * (point - origin);
      if (const std::optional<IkStop> interrupt = poll()) return interrupt;
    }
    return std::nullopt;
  });
}

}  // namespace armature
