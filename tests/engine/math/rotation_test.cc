#include <cmath>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/math/rotation.h"
#include "../testing/bvh_reference.h"

namespace armature {
namespace {

constexpr double kPi = std::numbers::pi;

// Angle of the rotation taking a to b (q and −q are the same rotation).
double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  const Eigen::Quaterniond d = a.conjugate() * b;
  return 2.0 * std::atan2(d.vec().norm(), std::abs(d.w()));
}

std::vector<Axis> Parse(const std::string& order) {
  std::vector<Axis> axes;
  for (char c : order) axes.push_back(static_cast<Axis>(c - 'X'));
  return axes;
}

// The product of axis matrices from cos/sin, independent of the engine.
Eigen::Matrix3d ReferenceEulerMatrix(const std::string& order, const std::vector<double>& radians) {
  Eigen::Matrix3d m = Eigen::Matrix3d::Identity();
  for (size_t i = 0; i < order.size(); ++i) m = m * testing::RefAxisMatrix(order[i], radians[i] * 180.0 / kPi);
  return m;
}

const std::vector<std::string> kTaitBryan = {"XYZ", "XZY", "YXZ", "YZX", "ZXY", "ZYX"};
const std::vector<std::string> kProperEuler = {"XYX", "XZX", "YXY", "YZY", "ZXZ", "ZYZ"};

// Angle triples for an order: generic ones and ones at and near gimbal lock
// (middle angle ±π/2 for Tait–Bryan, 0 or π for proper Euler).
std::vector<std::vector<double>> TestAngles(bool proper) {
  std::vector<std::vector<double>> out = {{0.3, -0.7, 1.1}, {-2.9, 0.4, 3.0}, {1.5, 1.2, -0.2}, {0, 0, 0}};
  const std::vector<double> locks = proper ? std::vector<double>{0.0, kPi} : std::vector<double>{kPi / 2, -kPi / 2};
  for (double lock : locks)
    for (double eps : {0.0, 1e-9, -1e-9, 1e-6, -1e-6, 1e-3}) out.push_back({0.8, lock + eps, -0.5});
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> any(-kPi, kPi);
  for (int i = 0; i < 50; ++i) out.push_back({any(rng), any(rng), any(rng)});
  return out;
}

TEST(Rotation, EulerToQuaternionMatchesAxisMatrixProduct) {
  for (bool proper : {false, true})
    for (const std::string& order : proper ? kProperEuler : kTaitBryan)
      for (const auto& a : TestAngles(proper)) {
        const Eigen::Matrix3d m = EulerToQuaternion(Parse(order), a).toRotationMatrix();
        EXPECT_LT((m - ReferenceEulerMatrix(order, a)).norm(), 1e-12) << order;
      }
}

TEST(Rotation, EulerRoundTripEveryThreeAxisOrder) {
  for (bool proper : {false, true})
    for (const std::string& order : proper ? kProperEuler : kTaitBryan)
      for (const auto& a : TestAngles(proper)) {
        const Eigen::Quaterniond q = EulerToQuaternion(Parse(order), a);
        double back[3];
        ASSERT_TRUE(QuaternionToEuler(q, Parse(order), back)) << order;
        EXPECT_LT(AngleBetween(q, EulerToQuaternion(Parse(order), back)), 1e-9) << order;
        // Away from the lock the angles themselves come back: without a hint
        // for Tait–Bryan (the solution with |middle| < π/2 is preferred, and
        // generated here), with the original angles as hint for proper Euler.
        const bool clear_of_lock = proper ? std::abs(std::sin(a[1])) > 1e-3 : std::cos(a[1]) > 1e-3;
        if (!clear_of_lock) continue;
        if (proper) ASSERT_TRUE(QuaternionToEuler(q, Parse(order), back, a));
        for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], a[k], 1e-9) << order << " angle " << k;
      }
}

TEST(Rotation, EulerRoundTripOneAndTwoAxes) {
  for (const std::string& order : {"X", "Y", "Z"})
    for (double a : {-3.0, -1.0, 0.0, 0.5, 2.9}) {
      const std::vector<double> in = {a};
      double back[1];
      ASSERT_TRUE(QuaternionToEuler(EulerToQuaternion(Parse(order), in), Parse(order), back));
      EXPECT_NEAR(back[0], a, 1e-12) << order;
    }
  // Includes a middle angle beyond π/2, where the three-axis decomposition's
  // preferred solution has a third angle of π that two axes cannot hold.
  for (const std::string& order : {"XY", "YX", "XZ", "ZX", "YZ", "ZY"})
    for (const std::vector<double>& in :
         std::vector<std::vector<double>>{{0.4, -0.3}, {-0.5, 2.0}, {2.5, -2.8}, {-3.0, 1.5707963}}) {
      const Eigen::Quaterniond q = EulerToQuaternion(Parse(order), in);
      double back[2];
      ASSERT_TRUE(QuaternionToEuler(q, Parse(order), back)) << order;
      EXPECT_LT(AngleBetween(q, EulerToQuaternion(Parse(order), back)), 1e-9) << order << " " << in[0] << "," << in[1];
      EXPECT_NEAR(back[0], in[0], 1e-6) << order;
      EXPECT_NEAR(back[1], in[1], 1e-6) << order;
    }
}

TEST(Rotation, EulerHintKeepsCurvesContinuousAcrossPi) {
  // A yaw sweeping past π: without a hint the angle wraps to −π, with the
  // previous frame as hint it keeps increasing.
  const std::vector<Axis> zxy = Parse("ZXY");
  std::vector<double> prev = {3.0, 0.2, -0.1};
  for (int i = 1; i <= 40; ++i) {
    const std::vector<double> truth = {3.0 + 0.01 * i, 0.2, -0.1};
    double back[3];
    QuaternionToEuler(EulerToQuaternion(zxy, truth), zxy, back, prev);
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(back[k], truth[k], 1e-9) << "frame " << i;
    prev.assign(back, back + 3);
  }
  double wrapped[3];
  QuaternionToEuler(EulerToQuaternion(zxy, std::vector<double>{3.3, 0.2, -0.1}), zxy, wrapped);
  EXPECT_NEAR(wrapped[0], 3.3 - 2 * kPi, 1e-9);
}

TEST(Rotation, ExpLogRoundTrip) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 200; ++i) {
    Eigen::Vector3d axis(u(rng), u(rng), u(rng));
    axis.normalize();
    for (double angle : {1e-14, 1e-8, 1e-3, 0.5, 2.0, kPi - 1e-6, kPi - 1e-9}) {
      const Eigen::Vector3d v = angle * axis;
      EXPECT_LT((LogQuaternion(ExpQuaternion(v)) - v).norm(), 1e-9 * std::max(1.0, angle)) << angle;
      EXPECT_LT((LogMatrix(ExpMatrix(v)) - v).norm(), 1e-8) << angle;
    }
  }
  // Angles beyond π come back as the equivalent rotation with angle in [0, π].
  const Eigen::Vector3d big(0, 0, 1.5 * kPi);
  EXPECT_LT((LogQuaternion(ExpQuaternion(big)) - Eigen::Vector3d(0, 0, -0.5 * kPi)).norm(), 1e-12);
}

TEST(Rotation, ExpMatrixAgreesWithEigenAngleAxis) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int i = 0; i < 100; ++i) {
    const Eigen::Vector3d axis = Eigen::Vector3d(u(rng), u(rng), u(rng)).normalized();
    const double angle = 4.0 * u(rng);
    const Eigen::Matrix3d expected = Eigen::AngleAxisd(angle, axis).toRotationMatrix();
    EXPECT_LT((ExpMatrix(angle * axis) - expected).norm(), 1e-12);
    EXPECT_LT((ExpQuaternion(angle * axis).toRotationMatrix() - expected).norm(), 1e-12);
  }
  EXPECT_TRUE(ExpMatrix(Eigen::Vector3d::Zero()).isIdentity());
}

TEST(Rotation, LogMatrixNearZeroAndPi) {
  const Eigen::Vector3d axis = Eigen::Vector3d(1, -2, 0.5).normalized();
  for (double angle : {1e-12, 1e-9, 1e-6, 1e-3}) {
    const Eigen::Vector3d v = LogMatrix(Eigen::AngleAxisd(angle, axis).toRotationMatrix());
    EXPECT_NEAR(v.norm(), angle, 1e-15 + 1e-9 * angle);
    EXPECT_LT((v.normalized() - axis).norm(), angle > 1e-9 ? 1e-6 : 1e-3);
  }
  for (double angle : {kPi - 1e-3, kPi - 1e-6, kPi - 1e-9, kPi}) {
    const Eigen::Vector3d v = LogMatrix(Eigen::AngleAxisd(angle, axis).toRotationMatrix());
    EXPECT_NEAR(v.norm(), angle, 1e-7);
    // At exactly π, axis and −axis are the same rotation.
    EXPECT_LT(std::min((v.normalized() - axis).norm(), (v.normalized() + axis).norm()), 1e-7);
    EXPECT_LT((ExpMatrix(v) - Eigen::AngleAxisd(angle, axis).toRotationMatrix()).norm(), 1e-9);
  }
}

TEST(Slerp, Endpoints) {
  const Eigen::Quaterniond a = ExpQuaternion({0.3, -0.2, 0.9});
  const Eigen::Quaterniond b = ExpQuaternion({-1.0, 0.5, 0.1});
  EXPECT_LT(AngleBetween(Slerp(a, b, 0.0), a), 1e-12);
  EXPECT_LT(AngleBetween(Slerp(a, b, 1.0), b), 1e-12);
  EXPECT_NEAR(Slerp(a, b, 0.37).norm(), 1.0, 1e-12);
}

TEST(Slerp, ConstantAngularSpeed) {
  const Eigen::Quaterniond a = ExpQuaternion({0.1, 0.2, -0.3});
  for (double total : {2.5, 0.4, 1e-3, 1e-6}) {
    const Eigen::Vector3d axis = Eigen::Vector3d(0.3, -1, 0.2).normalized();
    const Eigen::Quaterniond b = a * ExpQuaternion(total * axis);
    const int steps = 10;
    for (int i = 0; i < steps; ++i) {
      const double step = AngleBetween(Slerp(a, b, double(i) / steps), Slerp(a, b, double(i + 1) / steps));
      EXPECT_NEAR(step, total / steps, 1e-9 * total + 1e-15) << "total " << total << " step " << i;
    }
    // Midpoint: rotation about the same axis by half the angle.
    EXPECT_LT(AngleBetween(Slerp(a, b, 0.5), a * ExpQuaternion(0.5 * total * axis)), 1e-12);
  }
}

TEST(Slerp, TakesTheShortestArc) {
  const Eigen::Quaterniond a = Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond b = ExpQuaternion({0, 0, 2.0});
  const Eigen::Quaterniond neg_b(-b.coeffs());
  for (double t : {0.25, 0.5, 0.75}) {
    EXPECT_LT(AngleBetween(Slerp(a, b, t), Slerp(a, neg_b, t)), 1e-12);
    EXPECT_NEAR(AngleBetween(a, Slerp(a, neg_b, t)), 2.0 * t, 1e-12);
  }
  // 4 rad one way is 2π − 4 the other: slerp goes the short way.
  const Eigen::Quaterniond far = ExpQuaternion({0, 0, 4.0});
  const Eigen::Quaterniond far_other_way = ExpQuaternion({0, 0, 4.0 - 2 * kPi});
  EXPECT_LT(AngleBetween(Slerp(a, far, 0.5), ExpQuaternion({0, 0, 0.5 * (4.0 - 2 * kPi)})), 1e-12);
  EXPECT_NEAR(AngleBetween(a, Slerp(a, far, 1.0)), 2 * kPi - 4.0, 1e-12);
  EXPECT_LT(AngleBetween(Slerp(a, far_other_way, 0.5), Slerp(a, far, 0.5)), 1e-12);
}

TEST(Slerp, MatrixFormEqualsQuaternionForm) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-2, 2);
  for (int i = 0; i < 50; ++i) {
    const Eigen::Quaterniond a = ExpQuaternion({u(rng), u(rng), u(rng)});
    const Eigen::Quaterniond b = ExpQuaternion({u(rng), u(rng), u(rng)});
    for (double t : {0.0, 0.1, 0.5, 0.9, 1.0}) {
      const Eigen::Matrix3d m = SlerpMatrix(a.toRotationMatrix(), b.toRotationMatrix(), t);
      EXPECT_LT((m - Slerp(a, b, t).toRotationMatrix()).norm(), 1e-9) << t;
    }
  }
}

TEST(Squad, PassesThroughKeysAndEqualSpacingMatchesSquadControlPoint) {
  const Eigen::Quaterniond q0 = ExpQuaternion({0, 0, 0}), q1 = ExpQuaternion({0.5, 0.2, 0});
  const Eigen::Quaterniond q2 = ExpQuaternion({0.9, -0.3, 0.4}), q3 = ExpQuaternion({1.2, 0.1, 0.9});
  const Eigen::Quaterniond s1 = SquadControlPoint(q0, q1, q2), s2 = SquadControlPoint(q1, q2, q3);
  EXPECT_LT(AngleBetween(Squad(q1, s1, s2, q2, 0.0), q1), 1e-12);
  EXPECT_LT(AngleBetween(Squad(q1, s1, s2, q2, 1.0), q2), 1e-12);
  Eigen::Quaterniond in, out;
  SquadControlPoints(q0, q1, q2, 0.5, 0.5, &in, &out);
  EXPECT_LT(AngleBetween(in, s1), 1e-12);
  EXPECT_LT(AngleBetween(out, s1), 1e-12);
  // End keys get a one-sided tangent: the control point is the key itself.
  SquadControlPoints(q0, q1, q2, 0.0, 0.5, &in, &out);
  EXPECT_LT(AngleBetween(out, q1), 1e-12);
}

}  // namespace
}  // namespace armature
