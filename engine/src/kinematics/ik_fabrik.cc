#include "armature/engine/kinematics/ik_fabrik.h"

#include <optional>

#include "ik_internal.h"

namespace armature {
namespace {

// The point `length` from `anchor` in the direction of `p`.
Eigen::Vector3d Toward(const Eigen::Vector3d& anchor, const Eigen::Vector3d& p, double length) {
  const Eigen::Vector3d d = p - anchor;
  const double n = d.norm();
  return n > 1e-12 ? Eigen::Vector3d(anchor + d * (length / n)) : p;
}

}  // namespace

void SolveFabrik(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, IkResult& result) {
  const IkWorkspace::Effector& e = ws.effectors[0];
  // Chain top first: joint(i) for i < m, then the effector point.
  const int m = e.path_end - e.path_begin;
  auto joint = [&](int i) { return ws.paths[e.path_end - 1 - i]; };
  auto point_now = [&](int i) { return i < m ? ws.world_position[joint(i)] : ik_internal::EffectorPoint(ws, e); };
  // After turning `j`, the world transforms below it.
  auto refresh_below = [&](int j) {
    for (int k : ws.update)
      if (k > j) ik_internal::UpdateWorldOf(skeleton, ws, k);
  };
  ws.points.resize(m + 1);
  ws.lengths.resize(m);
  for (int i = 0; i < m; ++i) ws.lengths[i] = (point_now(i + 1) - point_now(i)).norm();

  // Each joint's turn refreshes the chain below it: look at the clock often.
  ik_internal::InterruptPoll poll(request, 8);
  ik_internal::SweepUntilReached(skeleton, request, ws, result, [&]() -> std::optional<IkStop> {
    std::vector<Eigen::Vector3d>& p = ws.points;
    for (int i = 0; i < m; ++i) p[i] = ws.world_position[joint(i)];
    const Eigen::Vector3d base = p[0];
    p[m] = e.target_position;
    for (int i = m - 1; i >= 0; --i) p[i] = Toward(p[i + 1], p[i], ws.lengths[i]);
    p[0] = base;
    for (int i = 0; i < m; ++i) p[i + 1] = Toward(p[i], p[i + 1], ws.lengths[i]);
    // Back to rotations, top down, re-reading each point from forward
    // kinematics so a limited joint's shortfall is passed down the chain.
    // A ball joint swings its bone onto the next point, then twists about
    // the bone to bring the point after onto its place (turning an elbow's
    // hinge plane towards the target); a hinge turns the first point that
    // lies off its axis (a twist hinge along the bone sees the one after).
    for (int i = 0; i < m; ++i) {
      const int j = joint(i);
      const Eigen::Vector3d origin = ws.world_position[j];
      if (const std::optional<Eigen::Vector3d> axis = ik_internal::HingeAxis(skeleton, request, ws, j)) {
        int k = i + 1;
        while (k < m && (point_now(k) - origin).cross(*axis).norm() < 1e-9 * ws.chain_length) ++k;
        ik_internal::TurnJointAbout(skeleton, request, ws, j, *axis, point_now(k), p[k]);
      } else {
        ik_internal::TurnJointTowards(skeleton, request, ws, j, point_now(i + 1), p[i + 1]);
        refresh_below(j);
        const Eigen::Vector3d bone = point_now(i + 1) - origin;
        if (i + 2 <= m && bone.norm() > 1e-12)
          ik_internal::TurnJointAbout(skeleton, request, ws, j, bone.normalized(), point_now(i + 2), p[i + 2]);
      }
      refresh_below(j);
      if (const std::optional<IkStop> interrupt = poll()) return interrupt;
    }
    return std::nullopt;
  });
}

}  // namespace armature
