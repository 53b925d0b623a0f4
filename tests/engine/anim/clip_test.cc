#include <cmath>
#include <numbers>
#include <random>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/clip.h"
#include "armature/engine/math/rotation.h"

namespace armature {
namespace {

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

Eigen::Quaterniond Rz(double a) { return Eigen::Quaterniond(Eigen::AngleAxisd(a, Eigen::Vector3d::UnitZ())); }

std::shared_ptr<Skeleton> OneJoint(Eigen::Vector3d rest_translation = Eigen::Vector3d(1, 2, 3)) {
  auto s = std::make_shared<Skeleton>();
  s->names = {"j"};
  s->parents = {-1};
  s->rest.resize(1);
  s->rest[0].translation = rest_translation;
  s->channels.resize(1);
  s->end_sites.resize(1);
  return s;
}

Clip OneJointClip(double duration) {
  Clip c;
  c.skeleton = OneJoint();
  c.joints.resize(1);
  c.duration = duration;
  return c;
}

// x-values 0, 2, 4 at uneven times 0, 1, 3.
Vec3Track UnevenTrack(Interpolation mode) {
  Vec3Track t;
  t.times = {0, 1, 3};
  t.values = {{0, 7, 0}, {2, 7, 0}, {4, 7, 0}};
  t.interpolation = mode;
  return t;
}

Trs Sample(const Clip& clip, double time, SampleOptions options = {}) {
  std::vector<Trs> out(1);
  EXPECT_TRUE(SampleClip(clip, time, options, out).ok());
  return out[0];
}

TEST(WrapTime, ClampAndLoop) {
  EXPECT_EQ(WrapTime(-0.5, 2.0, WrapMode::kClamp), 0.0);
  EXPECT_EQ(WrapTime(2.5, 2.0, WrapMode::kClamp), 2.0);
  EXPECT_EQ(WrapTime(1.25, 2.0, WrapMode::kClamp), 1.25);
  EXPECT_DOUBLE_EQ(WrapTime(2.5, 2.0, WrapMode::kLoop), 0.5);
  EXPECT_DOUBLE_EQ(WrapTime(-0.5, 2.0, WrapMode::kLoop), 1.5);
  EXPECT_DOUBLE_EQ(WrapTime(-2.5, 2.0, WrapMode::kLoop), 1.5);
  EXPECT_DOUBLE_EQ(WrapTime(7.0, 2.0, WrapMode::kLoop), 1.0);
  EXPECT_EQ(WrapTime(4.0, 2.0, WrapMode::kLoop), 0.0);
  EXPECT_EQ(WrapTime(-4.0, 2.0, WrapMode::kLoop), 0.0);
  EXPECT_EQ(WrapTime(3.0, 0.0, WrapMode::kLoop), 0.0);
  EXPECT_EQ(WrapTime(NAN, 2.0, WrapMode::kLoop), 0.0);
  // A tiny negative time must not wrap to `duration` itself.
  EXPECT_LT(WrapTime(-1e-300, 2.0, WrapMode::kLoop), 2.0);
}

TEST(SampleClip, StepValues) {
  Clip c = OneJointClip(3);
  c.joints[0].translation = UnevenTrack(Interpolation::kStep);
  EXPECT_EQ(Sample(c, 0.5).translation.x(), 0);
  EXPECT_EQ(Sample(c, 1.0).translation.x(), 2);
  EXPECT_EQ(Sample(c, 2.99).translation.x(), 2);
  EXPECT_EQ(Sample(c, 3.0).translation.x(), 4);
  EXPECT_EQ(Sample(c, 9.0).translation.x(), 4);  // clamped
}

TEST(SampleClip, LinearValues) {
  Clip c = OneJointClip(3);
  c.joints[0].translation = UnevenTrack(Interpolation::kLinear);
  EXPECT_DOUBLE_EQ(Sample(c, 0.5).translation.x(), 1.0);
  EXPECT_DOUBLE_EQ(Sample(c, 2.0).translation.x(), 3.0);
  EXPECT_DOUBLE_EQ(Sample(c, 2.5).translation.x(), 3.5);
  EXPECT_DOUBLE_EQ(Sample(c, 2.0).translation.y(), 7.0);
}

// Hermite with slopes from the parabola through neighbouring keys:
// key slopes 2, (1·1 + 2·2)/3 = 5/3 and 1 (one-sided at the end);
// at the segment midpoint p = (p0 + p1)/2 + h·(m0 − m1)/8.
TEST(SampleClip, CubicValuesHandDerived) {
  Clip c = OneJointClip(3);
  c.joints[0].translation = UnevenTrack(Interpolation::kCubic);
  EXPECT_NEAR(Sample(c, 0.5).translation.x(), 1.0 + 1.0 * (2.0 - 5.0 / 3.0) / 8.0, 1e-12);  // 25/24
  EXPECT_NEAR(Sample(c, 2.0).translation.x(), 3.0 + 2.0 * (5.0 / 3.0 - 1.0) / 8.0, 1e-12);  // 19/6
  EXPECT_NEAR(Sample(c, 1.0).translation.x(), 2.0, 1e-12);
  EXPECT_NEAR(Sample(c, 2.0).translation.y(), 7.0, 1e-12);
}

TEST(SampleClip, CubicReproducesAQuadraticAtUnevenKeys) {
  Clip c = OneJointClip(3.5);
  Vec3Track& t = c.joints[0].translation;
  t.interpolation = Interpolation::kCubic;
  auto f = [](double x) { return x * x - 2 * x; };
  for (double x : {0.0, 0.5, 1.5, 2.0, 3.5}) {
    t.times.push_back(x);
    t.values.emplace_back(f(x), 0, 0);
  }
  for (double x : {0.6, 1.0, 1.2, 1.7, 1.9})  // interior segments: both key slopes exact
    EXPECT_NEAR(Sample(c, x).translation.x(), f(x), 1e-12) << x;
}

TEST(SampleClip, GltfCubicSplineUsesTheFileTangents) {
  Clip c = OneJointClip(2);
  Vec3Track& t = c.joints[0].translation;
  t.interpolation = Interpolation::kCubic;
  t.times = {0, 2};
  t.values = {{1, 0, 0}, {3, 0, 0}};
  t.in_tangents = {{0, 0, 0}, {-1, 0, 0}};
  t.out_tangents = {{4, 0, 0}, {0, 0, 0}};
  // p(½) = ½·1 + ⅛·(2·4) + ½·3 − ⅛·(2·(−1)) = 3.25
  EXPECT_NEAR(Sample(c, 1.0).translation.x(), 3.25, 1e-12);
  // LINEAR override ignores the tangents.
  SampleOptions linear;
  linear.interpolation = Interpolation::kLinear;
  EXPECT_NEAR(Sample(c, 1.0, linear).translation.x(), 2.0, 1e-12);

  // Rotations: Hermite on the components, then normalize.
  Clip r = OneJointClip(2);
  QuatTrack& q = r.joints[0].rotation;
  q.interpolation = Interpolation::kCubic;
  q.times = {0, 2};
  q.values = {Eigen::Quaterniond::Identity(), Rz(std::numbers::pi / 2)};
  q.out_tangents = {Eigen::Quaterniond(0, 0, 0, 0.3), Eigen::Quaterniond(0, 0, 0, 0)};
  q.in_tangents = {Eigen::Quaterniond(0, 0, 0, 0), Eigen::Quaterniond(-0.1, 0, 0, 0.2)};
  const Eigen::Vector4d expected = (0.5 * q.values[0].coeffs() + 0.125 * 2 * q.out_tangents[0].coeffs() +
                                    0.5 * q.values[1].coeffs() - 0.125 * 2 * q.in_tangents[1].coeffs())
                                       .normalized();
  EXPECT_LT((Sample(r, 1.0).rotation.coeffs() - expected).norm(), 1e-12);
}

TEST(SampleClip, RotationStepLinearAndSquad) {
  Clip c = OneJointClip(3);
  QuatTrack& q = c.joints[0].rotation;
  q.times = {0, 1, 3};
  q.values = {Rz(0), Rz(2), Rz(4)};
  q.interpolation = Interpolation::kStep;
  EXPECT_LT(AngleBetween(Sample(c, 0.9).rotation, Rz(0)), 1e-12);
  q.interpolation = Interpolation::kLinear;
  EXPECT_LT(AngleBetween(Sample(c, 0.25).rotation, Rz(0.5)), 1e-12);
  EXPECT_LT(AngleBetween(Sample(c, 2.0).rotation, Rz(3.0)), 1e-12);
  // About one axis squad is the Hermite spline of the angle with the same
  // slopes as the vector case: 25/24 and 19/6 rad.
  q.interpolation = Interpolation::kCubic;
  EXPECT_LT(AngleBetween(Sample(c, 0.5).rotation, Rz(25.0 / 24.0)), 1e-12);
  EXPECT_LT(AngleBetween(Sample(c, 2.0).rotation, Rz(19.0 / 6.0)), 1e-12);
}

TEST(SampleClip, SquadPassesThroughKeysWithFlippedSigns) {
  Clip c = OneJointClip(2.5);
  QuatTrack& q = c.joints[0].rotation;
  q.interpolation = Interpolation::kCubic;
  q.times = {0, 0.4, 1.5, 2.5};
  q.values = {ExpQuaternion({0.1, 0.2, 0.3}), ExpQuaternion({0.8, -0.4, 0.1}), ExpQuaternion({-0.2, 1.1, 0.5}),
              ExpQuaternion({0.3, 0.3, -0.9})};
  q.values[2].coeffs() *= -1;  // same rotation, other hemisphere
  for (size_t k = 0; k < q.times.size(); ++k)
    EXPECT_LT(AngleBetween(Sample(c, q.times[k]).rotation, q.values[k]), 1e-12);
  for (double t = 0; t <= 2.5; t += 0.05) EXPECT_NEAR(Sample(c, t).rotation.norm(), 1.0, 1e-12);
}

// A time on a key gives that key, normalized, bit for bit in every mode (no
// slerp is evaluated there: compression samples a clip at its own frames).
TEST(SampleClip, ATimeOnAKeyGivesTheKeyExactly) {
  Clip c = OneJointClip(2.5);
  QuatTrack& q = c.joints[0].rotation;
  q.times = {0, 0.4, 1.5, 2.5};
  q.values = {ExpQuaternion({0.1, 0.2, 0.3}), ExpQuaternion({0.8, -0.4, 0.1}), ExpQuaternion({-0.2, 1.1, 0.5}),
              ExpQuaternion({0.3, 0.3, -0.9})};
  q.values[1].coeffs() *= 1.5;  // not unit: the sample is the key normalized
  for (Interpolation mode : {Interpolation::kStep, Interpolation::kLinear, Interpolation::kCubic}) {
    q.interpolation = mode;
    for (size_t k = 0; k < q.times.size(); ++k)
      EXPECT_EQ(Sample(c, q.times[k]).rotation.coeffs(), q.values[k].normalized().coeffs())
          << "mode " << static_cast<int>(mode) << ", key " << k;
  }
}

// Body-frame angular velocity by one-sided finite differences.
Eigen::Vector3d VelocityAfter(const Clip& c, double t, double h) {
  return LogQuaternion(Sample(c, t).rotation.conjugate() * Sample(c, t + h).rotation) / h;
}
Eigen::Vector3d VelocityBefore(const Clip& c, double t, double h) {
  return LogQuaternion(Sample(c, t - h).rotation.conjugate() * Sample(c, t).rotation) / h;
}

TEST(SampleClip, CubicIsC1AcrossUnevenKeys) {
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> u(-1.2, 1.2);
  Clip c = OneJointClip(3.2);
  QuatTrack& q = c.joints[0].rotation;
  Vec3Track& v = c.joints[0].translation;
  q.interpolation = v.interpolation = Interpolation::kCubic;
  for (double t : {0.0, 0.3, 1.2, 1.5, 2.6, 3.2}) {
    q.times.push_back(t);
    q.values.push_back(ExpQuaternion({u(rng), u(rng), u(rng)}));
    if (q.values.size() % 2 == 0) q.values.back().coeffs() *= -1;
    v.times.push_back(t);
    v.values.emplace_back(u(rng), u(rng), u(rng));
  }
  const double h = 1e-6;
  for (size_t k = 1; k + 1 < q.times.size(); ++k) {
    const double t = q.times[k];
    const Eigen::Vector3d w_before = VelocityBefore(c, t, h), w_after = VelocityAfter(c, t, h);
    EXPECT_LT((w_before - w_after).norm(), 1e-4 * (1 + w_after.norm())) << "rotation at key " << k;
    const Eigen::Vector3d d_before = (Sample(c, t).translation - Sample(c, t - h).translation) / h;
    const Eigen::Vector3d d_after = (Sample(c, t + h).translation - Sample(c, t).translation) / h;
    EXPECT_LT((d_before - d_after).norm(), 1e-4 * (1 + d_after.norm())) << "translation at key " << k;
  }
  // The check can fail: LINEAR has corners at the keys.
  SampleOptions linear;
  linear.interpolation = Interpolation::kLinear;
  const double t = q.times[2];
  const Eigen::Vector3d lin_before =
      LogQuaternion(Sample(c, t - h, linear).rotation.conjugate() * Sample(c, t, linear).rotation) / h;
  const Eigen::Vector3d lin_after =
      LogQuaternion(Sample(c, t, linear).rotation.conjugate() * Sample(c, t + h, linear).rotation) / h;
  EXPECT_GT((lin_before - lin_after).norm(), 0.1);
}

TEST(SampleClip, LoopWrapsAndEmptyTracksKeepRest) {
  Clip c = OneJointClip(3);
  c.joints[0].translation = UnevenTrack(Interpolation::kLinear);
  SampleOptions loop;
  loop.wrap = WrapMode::kLoop;
  EXPECT_DOUBLE_EQ(Sample(c, 3.5, loop).translation.x(), 1.0);
  EXPECT_DOUBLE_EQ(Sample(c, -1.0, loop).translation.x(), 3.0);
  EXPECT_DOUBLE_EQ(Sample(c, -1.0).translation.x(), 0.0);

  Clip rest = OneJointClip(1);
  const Trs r = Sample(rest, 0.5);
  EXPECT_EQ(r.translation, Eigen::Vector3d(1, 2, 3));
  EXPECT_TRUE(r.rotation.coeffs().isApprox(Eigen::Quaterniond::Identity().coeffs()));
  EXPECT_EQ(r.scale, Eigen::Vector3d::Ones());
}

TEST(SampleClip, OptionOverridesTrackInterpolation) {
  Clip c = OneJointClip(3);
  c.joints[0].translation = UnevenTrack(Interpolation::kCubic);
  SampleOptions step;
  step.interpolation = Interpolation::kStep;
  EXPECT_EQ(Sample(c, 0.5, step).translation.x(), 0.0);
  c.joints[0].scale = UnevenTrack(Interpolation::kStep);
  EXPECT_EQ(Sample(c, 0.5).scale.x(), 0.0);                         // the track's own STEP
  EXPECT_NEAR(Sample(c, 0.5).translation.x(), 25.0 / 24.0, 1e-12);  // the track's own CUBIC
}

TEST(SampleClip, RejectsBadCalls) {
  Clip c = OneJointClip(1);
  std::vector<Trs> two(2);
  Status st = SampleClip(c, 0.0, {}, two);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("1 joints"), std::string::npos) << st.message();
  std::vector<Trs> one(1);
  EXPECT_EQ(SampleClip(c, NAN, {}, one).code(), StatusCode::kInvalidArgument);
  Clip no_skeleton;
  EXPECT_EQ(SampleClip(no_skeleton, 0.0, {}, one).code(), StatusCode::kInvalidArgument);
}

TEST(SampleClip, SharedConstClipSampledFromManyThreads) {
  Clip c = OneJointClip(3);
  c.joints[0].translation = UnevenTrack(Interpolation::kCubic);
  c.joints[0].rotation.interpolation = Interpolation::kCubic;
  c.joints[0].rotation.times = {0, 1, 3};
  c.joints[0].rotation.values = {Rz(0), ExpQuaternion({0.3, 1, 0}), Rz(2)};
  const Clip& shared = c;
  std::vector<double> expected;
  for (int i = 0; i < 300; ++i) expected.push_back(Sample(shared, i * 0.01).rotation.w());
  std::vector<int> mismatches(4, 0);
  std::vector<std::thread> threads;
  for (int k = 0; k < 4; ++k)
    threads.emplace_back([&, k] {
      std::vector<Trs> out(1);
      for (int rep = 0; rep < 50; ++rep)
        for (int i = 0; i < 300; ++i) {
          (void)SampleClip(shared, i * 0.01, {}, out);
          if (out[0].rotation.w() != expected[static_cast<size_t>(i)]) ++mismatches[static_cast<size_t>(k)];
        }
    });
  for (auto& t : threads) t.join();
  for (int m : mismatches) EXPECT_EQ(m, 0);
}

TEST(ClipValidate, NamesTheProblem) {
  Clip c = OneJointClip(3);
  EXPECT_TRUE(c.Validate().ok());
  c.joints[0].translation = UnevenTrack(Interpolation::kLinear);
  EXPECT_TRUE(c.Validate().ok());
  c.joints[0].translation.times = {0, 1, 1};
  Status st = c.Validate();
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("joint 'j' translation track: key 2"), std::string::npos) << st.message();
  c.joints[0].translation.times = {0, 1};
  EXPECT_NE(c.Validate().message().find("3 values for 2 key times"), std::string::npos) << c.Validate().message();
  c.joints[0].translation = {};
  c.joints[0].rotation.times = {0};
  c.joints[0].rotation.values = {Eigen::Quaterniond(2, 0, 0, 0)};
  EXPECT_NE(c.Validate().message().find("not a unit quaternion"), std::string::npos);
  c.joints[0].rotation.values = {Eigen::Quaterniond(NAN, 0, 0, 0)};
  EXPECT_NE(c.Validate().message().find("not finite"), std::string::npos);
  c.joints[0].rotation = {};
  c.joints[0].scale = UnevenTrack(Interpolation::kCubic);
  c.joints[0].scale.in_tangents.resize(3);
  EXPECT_NE(c.Validate().message().find("tangents"), std::string::npos);
  c.joints.clear();
  EXPECT_NE(c.Validate().message().find("0 joint tracks"), std::string::npos);
  Clip w = OneJointClip(1);
  w.weights.push_back({"mesh", 2, {0, 1}, {0, 1, 2}, Interpolation::kLinear});
  EXPECT_NE(w.Validate().message().find("weights track of mesh 'mesh'"), std::string::npos);
}

TEST(SampleWeights, StepLinearAndCubicSpline) {
  WeightsTrack w{"m", 2, {0, 1, 3}, {0, 1, 1, 0, 0.5, 0.5}, Interpolation::kLinear};
  double out[2];
  SampleWeights(w, 0.5, {}, out);
  EXPECT_DOUBLE_EQ(out[0], 0.5);
  EXPECT_DOUBLE_EQ(out[1], 0.5);
  SampleWeights(w, 2.0, {}, out);
  EXPECT_DOUBLE_EQ(out[0], 0.75);
  EXPECT_DOUBLE_EQ(out[1], 0.25);
  SampleOptions step;
  step.interpolation = Interpolation::kStep;
  SampleWeights(w, 2.0, step, out);
  EXPECT_EQ(out[0], 1.0);
  SampleOptions loop;
  loop.wrap = WrapMode::kLoop;
  SampleWeights(w, 3.5, loop, out);
  EXPECT_DOUBLE_EQ(out[0], 0.5);

  // glTF CUBICSPLINE layout: per key in-tangents, values, out-tangents.
  WeightsTrack c{"m", 1, {0, 2}, {0, 1, 4, -1, 3, 0}, Interpolation::kCubic};
  double one[1];
  SampleWeights(c, 1.0, {}, one);
  EXPECT_NEAR(one[0], 3.25, 1e-12);
  // Plain values with CUBIC: the same spline as vector tracks.
  WeightsTrack p{"m", 1, {0, 1, 3}, {0, 2, 4}, Interpolation::kCubic};
  SampleWeights(p, 0.5, {}, one);
  EXPECT_NEAR(one[0], 25.0 / 24.0, 1e-12);
}

}  // namespace
}  // namespace armature
