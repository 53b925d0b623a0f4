// FillCubicTangents: the tangents a CUBIC track without them implies, so it
// can be stored as glTF CUBICSPLINE (see CreateClip).
#include <cmath>
#include <optional>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/cubic_tangents.h"
#include "armature/engine/math/rotation.h"

namespace armature {
namespace {

Trs Sample(const JointTrack& track, double t) {
  Trs out;
  SampleJoint(track, t, std::nullopt, out);
  return out;
}

// Translations: with the filled tangents, sampling is exactly the
// Catmull-Rom sampling of the same keys without them.
TEST(CubicTangents, FilledVectorTangentsSampleAsCatmullRom) {
  JointTrack plain;
  plain.translation.interpolation = Interpolation::kCubic;
  plain.translation.times = {0, 0.3, 0.5, 1.2, 1.3};
  plain.translation.values = {{0, 0, 0}, {1, -2, 0.5}, {0.5, 3, 1}, {-1, 0, 2}, {2, 1, -1}};
  JointTrack filled = plain;
  FillCubicTangents(filled.translation);
  ASSERT_EQ(filled.translation.in_tangents.size(), 5u);
  for (double t = 0; t <= 1.3; t += 0.01)
    EXPECT_LT((Sample(filled, t).translation - Sample(plain, t).translation).norm(), 1e-12) << t;
}

// Rotations: the keys stay the same rotations (signs flipped into one
// hemisphere), the curve passes through them and is C¹ at each.
TEST(CubicTangents, FilledRotationTangentsGiveAC1CurveThroughTheKeys) {
  JointTrack track;
  QuatTrack& r = track.rotation;
  r.interpolation = Interpolation::kCubic;
  r.times = {0, 0.4, 0.7, 1.5};
  for (int k = 0; k < 4; ++k) {
    Eigen::Quaterniond q(Eigen::AngleAxisd(0.9 * (k % 2 ? 1 : -1), Eigen::Vector3d(1, k, 0.5).normalized()));
    if (k == 2) q.coeffs() = -q.coeffs();  // the same rotation, the other sign
    r.values.push_back(q);
  }
  const std::vector<Eigen::Quaterniond> given = r.values;
  FillCubicTangents(r);
  for (size_t k = 0; k < 4; ++k) {
    EXPECT_LT(given[k].angularDistance(r.values[k]), 1e-12);
    if (k > 0) EXPECT_GE(r.values[k].dot(r.values[k - 1]), 0);
    EXPECT_LT(Sample(track, r.times[k]).rotation.angularDistance(r.values[k]), 1e-12);
  }
  const double h = 1e-5;
  for (size_t k = 1; k + 1 < 4; ++k) {
    const double t = r.times[k];
    auto at = [&](double s) {
      return Eigen::Vector4d(SameHemisphere(Sample(track, s).rotation, r.values[k]).coeffs());
    };
    const Eigen::Vector4d left = (at(t) - at(t - h)) / h, right = (at(t + h) - at(t)) / h;
    EXPECT_LT((left - right).norm(), 1e-3 * std::max(1.0, left.norm())) << "key " << k;
  }
}

}  // namespace
}  // namespace armature
