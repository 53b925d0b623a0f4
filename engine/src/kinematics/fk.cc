#include "armature/engine/kinematics/fk.h"

#include <cmath>
#include <string>

#include "kinematics/fk_kernels.h"

namespace armature {

// Trs::ToAffine and the affine product written out on the 3×4 part: no
// identity fill, no temporary, and no scale product for unscaled joints
// (BVH joints, most glTF joints). Each world column is the parent's columns
// weighted by the local column, summed left to right ((c0·a + c1·b) + c2·c),
// the order the AVX2 kernel keeps; Eigen's 3×3 product sums its third row
// in another order, so the two would differ in the last bit.
void ComputeWorldScalar(const Skeleton& skeleton, std::span<const Trs> local, std::span<Eigen::Affine3d> world) {
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
      const auto c0 = pw.col(0).head<3>(), c1 = pw.col(1).head<3>(), c2 = pw.col(2).head<3>();
      for (int j = 0; j < 3; ++j) w.col(j).head<3>() = c0 * r(0, j) + c1 * r(1, j) + c2 * r(2, j);
      const Eigen::Vector3d& t = l.translation;
      w.col(3).head<3>() = c0 * t.x() + c1 * t.y() + c2 * t.z() + pw.col(3).head<3>();
    }
    w.row(3) << 0, 0, 0, 1;
  }
}

namespace {

// Byte offset of a member inside the Trs `t`.
size_t OffsetIn(const Trs& t, const double* member) {
  return static_cast<size_t>(reinterpret_cast<const char*>(member) - reinterpret_cast<const char*>(&t));
}

// The kernels' view of a pose (world rotations aside).
fk_internal::FkInput KernelInput(const Skeleton& skeleton, std::span<const Trs> local,
                                 std::span<Eigen::Affine3d> world) {
  static_assert(sizeof(Eigen::Affine3d) == 16 * sizeof(double), "the kernel writes 16 doubles a joint");
  static const Trs layout;
  fk_internal::FkInput in;
  in.joints = skeleton.size();
  in.parents = skeleton.parents.data();
  in.local = reinterpret_cast<const char*>(local.data());
  in.local_stride = sizeof(Trs);
  in.translation_offset = OffsetIn(layout, layout.translation.data());
  in.rotation_offset = OffsetIn(layout, layout.rotation.coeffs().data());
  in.scale_offset = OffsetIn(layout, layout.scale.data());
  in.world = world.data()->matrix().data();
  return in;
}

// a·b summed by b's components, ((bw·a + bx·a1) + by·a2) + bz·a3 with a1..a3
// signed permutations of a: the order the AVX2 kernel keeps (Eigen's own
// product sums in another, a last-bit difference).
Eigen::Quaterniond QuaternionProduct(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const double ax = a.x(), ay = a.y(), az = a.z(), aw = a.w();
  const double bx = b.x(), by = b.y(), bz = b.z(), bw = b.w();
  return Eigen::Quaterniond(((bw * aw + bx * -ax) + by * -ay) + bz * -az,  // w
                            ((bw * ax + bx * aw) + by * -az) + bz * ay,    // x
                            ((bw * ay + bx * az) + by * aw) + bz * -ax,    // y
                            ((bw * az + bx * -ay) + by * ax) + bz * aw);   // z
}

bool UseAvx2() {
  static const bool use_avx2 = fk_internal::avx2::Available();
  return use_avx2;
}

}  // namespace

void ComputeWorld(const Skeleton& skeleton, std::span<const Trs> local, std::span<Eigen::Affine3d> world) {
  if (!UseAvx2() || skeleton.size() == 0) return ComputeWorldScalar(skeleton, local, world);
  fk_internal::avx2::ComputeWorld(KernelInput(skeleton, local, world));
}

void ComputeWorldScalar(const Skeleton& skeleton, std::span<const Trs> local, std::span<Eigen::Affine3d> world,
                        std::span<Eigen::Quaterniond> world_rotation) {
  ComputeWorldScalar(skeleton, local, world);
  for (size_t i = 0; i < skeleton.size(); ++i) {
    const int p = skeleton.parents[i];
    world_rotation[i] =
        p < 0 ? local[i].rotation : QuaternionProduct(world_rotation[static_cast<size_t>(p)], local[i].rotation);
  }
}

void ComputeWorld(const Skeleton& skeleton, std::span<const Trs> local, std::span<Eigen::Affine3d> world,
                  std::span<Eigen::Quaterniond> world_rotation) {
  static_assert(sizeof(Eigen::Quaterniond) == 4 * sizeof(double), "the kernel writes 4 doubles a joint");
  if (!UseAvx2() || skeleton.size() == 0) return ComputeWorldScalar(skeleton, local, world, world_rotation);
  const fk_internal::FkInput in = KernelInput(skeleton, local, world);
  fk_internal::avx2::ComputeWorld(in);
  fk_internal::avx2::ComputeWorldRotations(in, world_rotation.data()->coeffs().data());
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
