#include "armature/engine/kinematics/fk.h"

#include <cmath>
#include <string>

namespace armature {

void ComputeWorld(const Skeleton& skeleton, std::span<const Trs> local, std::span<Eigen::Affine3d> world) {
  // Trs::ToAffine and the affine product written out on the 3×4 part: no
  // identity fill, no temporary, and no scale product for unscaled joints
  // (BVH joints, most glTF joints).
  const size_t n = skeleton.size();
  for (size_t i = 0; i < n; ++i) {
    const Trs& l = local[i];
    Eigen::Matrix3d r = l.rotation.toRotationMatrix();
    if (l.scale.x() != 1 || l.scale.y() != 1 || l.scale.z() != 1) r = r * l.scale.asDiagonal();
    Eigen::Matrix4d& w = world[i].matrix();
    const int p = skeleton.parents[i];
    if (p < 0) {
      w.topLeftCorner<3, 3>() = r;
      w.topRightCorner<3, 1>() = l.translation;
    } else {
      const Eigen::Matrix4d& pw = world[static_cast<size_t>(p)].matrix();
      w.topLeftCorner<3, 3>().noalias() = pw.topLeftCorner<3, 3>() * r;
      w.topRightCorner<3, 1>().noalias() = pw.topLeftCorner<3, 3>() * l.translation + pw.topRightCorner<3, 1>();
    }
    w.row(3) << 0, 0, 0, 1;
  }
}

void ComputeWorld(const Skeleton& skeleton, std::span<const Trs> local, std::span<Eigen::Affine3d> world,
                  std::span<Eigen::Quaterniond> world_rotation) {
  ComputeWorld(skeleton, local, world);
  for (size_t i = 0; i < skeleton.size(); ++i) {
    const int p = skeleton.parents[i];
    world_rotation[i] = p < 0 ? local[i].rotation : world_rotation[static_cast<size_t>(p)] * local[i].rotation;
  }
}

Status PoseFromArrays(const Skeleton& skeleton, std::span<const float> rotations, std::span<const float> translations,
                      std::span<Trs> out) {
  const size_t n = skeleton.size();
  if (rotations.size() != 4 * n && !rotations.empty())
    return Status::InvalidArgument("pose.rotations: expected " + std::to_string(4 * n) + " values (w,x,y,z for " +
                                   std::to_string(n) + " joints), got " + std::to_string(rotations.size()));
  if (!translations.empty() && translations.size() != 3 && translations.size() != 3 * n)
    return Status::InvalidArgument("pose.translations: expected 0, 3 (root) or " + std::to_string(3 * n) +
                                   " values, got " + std::to_string(translations.size()));
  for (size_t i = 0; i < n; ++i) {
    out[i] = skeleton.rest[i];
    if (!rotations.empty()) {
      Eigen::Quaterniond q(rotations[4 * i], rotations[4 * i + 1], rotations[4 * i + 2], rotations[4 * i + 3]);
      const double norm = q.norm();
      if (!std::isfinite(norm) || norm < 1e-6)
        return Status::InvalidArgument("pose.rotations: joint '" + skeleton.names[i] +
                                       "' has a zero-length or non-finite quaternion");
      out[i].rotation = Eigen::Quaterniond(q.coeffs() / norm);
    }
  }
  const size_t given = translations.size() / 3;
  for (size_t i = 0; i < given; ++i) {
    const Eigen::Vector3d t(translations[3 * i], translations[3 * i + 1], translations[3 * i + 2]);
    if (!t.allFinite())
      return Status::InvalidArgument("pose.translations: joint '" + skeleton.names[i] + "' is not finite");
    out[i].translation = t;
  }
  return Status::Ok();
}

}  // namespace armature
