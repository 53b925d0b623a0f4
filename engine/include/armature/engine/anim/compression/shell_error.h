// ACL's error metric: the world-space displacement of virtual points at a
// shell distance from each joint, along its local x, y and z axes, between a
// lossy pose and the reference (the clip as stored). World transforms are
// composed as ACL's qvvf metric does (rotation, translation, per-axis scale).
#pragma once

#include <cstddef>
#include <functional>
#include <span>
#include <vector>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/skeleton.h"
#include "armature/engine/math/transform.h"

namespace armature {

// A joint's world transform as ACL's qvv: world = parent ∘ local.
struct WorldQvv {
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d scale = Eigen::Vector3d::Ones();

  Eigen::Vector3d Apply(const Eigen::Vector3d& point) const {
    return translation + rotation * scale.cwiseProduct(point);
  }
};

// world[i] = world[parent(i)] ∘ local[i].
void ComposeWorldQvv(const Skeleton& skeleton, std::span<const Trs> local, std::span<WorldQvv> world);

// Measures poses of one skeleton; holds its scratch (no allocation per pose).
class ShellErrorMeter {
 public:
  ShellErrorMeter(const Skeleton& skeleton, double shell_distance);

  // Per joint: the largest displacement of its three virtual points.
  void Measure(std::span<const Trs> reference, std::span<const Trs> lossy, std::span<double> per_joint);
  // The same against a reference already in world space.
  void MeasureWorld(std::span<const WorldQvv> reference, std::span<const Trs> lossy, std::span<double> per_joint);

 private:
  const Skeleton& skeleton_;
  double shell_;
  std::vector<WorldQvv> reference_, lossy_;
};

// The error over every joint of every frame: its 99th percentile and worst.
struct ClipError {
  double p99 = 0;
  double worst = 0;
};

// The 99th percentile and worst of per-joint, per-frame errors.
ClipError SummarizeErrors(std::vector<double> errors);

// A clip's frames: `count` poses `frame_time` apart from time 0.
struct FrameGrid {
  size_t count = 0;
  double frame_time = 0;
  double Time(size_t frame) const { return static_cast<double>(frame) * frame_time; }
};

using PoseSampler = std::function<Status(double time, std::span<Trs> out)>;

// `lossy` against SampleClip(reference) at every frame of `frames`.
StatusOr<ClipError> MeasureClipError(const Clip& reference, const FrameGrid& frames, double shell_distance,
                                     const PoseSampler& lossy);

}  // namespace armature
