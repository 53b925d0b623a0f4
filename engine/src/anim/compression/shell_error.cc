#include "armature/engine/anim/compression/shell_error.h"

#include <algorithm>
#include <cmath>

namespace armature {

void ComposeWorldQvv(const Skeleton& skeleton, std::span<const Trs> local, std::span<WorldQvv> world) {
  for (size_t i = 0; i < skeleton.size(); ++i) {
    const Trs& l = local[i];
    const int parent = skeleton.parents[i];
    if (parent < 0) {
      world[i] = {l.rotation, l.translation, l.scale};
      continue;
    }
    const WorldQvv& p = world[parent];
    world[i].translation = p.Apply(l.translation);
    world[i].rotation = p.rotation * l.rotation;
    world[i].scale = p.scale.cwiseProduct(l.scale);
  }
}

ShellErrorMeter::ShellErrorMeter(const Skeleton& skeleton, double shell_distance)
    : skeleton_(skeleton), shell_(shell_distance), reference_(skeleton.size()), lossy_(skeleton.size()) {}

void ShellErrorMeter::Measure(std::span<const Trs> reference, std::span<const Trs> lossy, std::span<double> per_joint) {
  ComposeWorldQvv(skeleton_, reference, reference_);
  MeasureWorld(reference_, lossy, per_joint);
}

void ShellErrorMeter::MeasureWorld(std::span<const WorldQvv> reference, std::span<const Trs> lossy,
                                   std::span<double> per_joint) {
  ComposeWorldQvv(skeleton_, lossy, lossy_);
  // A point on axis a lands at translation + shell · scale_a · column a of
  // the rotation matrix: one matrix per transform serves its three points.
  for (size_t i = 0; i < skeleton_.size(); ++i) {
    const WorldQvv &r = reference[i], &l = lossy_[i];
    const Eigen::Matrix3d rm = r.rotation.toRotationMatrix(), lm = l.rotation.toRotationMatrix();
    const Eigen::Vector3d moved = r.translation - l.translation;
    double worst = 0;
    for (int axis = 0; axis < 3; ++axis)
      worst = std::max(
          worst,
          (moved + rm.col(axis) * (r.scale[axis] * shell_) - lm.col(axis) * (l.scale[axis] * shell_)).squaredNorm());
    per_joint[i] = std::sqrt(worst);
  }
}

StatusOr<ClipError> MeasureClipError(const Clip& reference, const FrameGrid& frames, double shell_distance,
                                     const PoseSampler& lossy) {
  if (!reference.skeleton) return Status::InvalidArgument("clip has no skeleton");
  const Skeleton& skeleton = *reference.skeleton;
  const size_t n = skeleton.size();
  ShellErrorMeter meter(skeleton, shell_distance);
  std::vector<Trs> expected(n), actual(n);
  std::vector<double> per_joint(n), all;
  all.reserve(frames.count * n);
  for (size_t f = 0; f < frames.count; ++f) {
    const double t = frames.Time(f);
    ARMATURE_RETURN_IF_ERROR(SampleClip(reference, t, {}, expected));
    ARMATURE_RETURN_IF_ERROR(lossy(t, actual));
    meter.Measure(expected, actual, per_joint);
    all.insert(all.end(), per_joint.begin(), per_joint.end());
  }
  return SummarizeErrors(std::move(all));
}

ClipError SummarizeErrors(std::vector<double> errors) {
  ClipError e;
  if (errors.empty()) return e;
  const size_t at =
      std::min(errors.size() - 1, static_cast<size_t>(std::ceil(0.99 * static_cast<double>(errors.size()))) - 1);
  std::nth_element(errors.begin(), errors.begin() + static_cast<std::ptrdiff_t>(at), errors.end());
  e.p99 = errors[at];
  e.worst = *std::max_element(errors.begin() + static_cast<std::ptrdiff_t>(at), errors.end());
  return e;
}

}  // namespace armature
