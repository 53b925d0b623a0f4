#include "armature/engine/math/rotation.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>

#include <Eigen/Eigenvalues>

namespace armature {
namespace {

Eigen::Vector3d UnitAxis(Axis a) { return Eigen::Vector3d::Unit(static_cast<int>(a)); }

// sin(tθ)/sin θ for cos θ = d near 1 and t in [0, 1], without acos, sin or
// cos (the motion blend's hot path: its layers' rotations are mostly close).
// Eberly's series ("A Fast and Accurate Algorithm for Computing SLERP",
// 2011): Σ b_i (d − 1)^i, b_0 = t, b_i = b_{i−1}·(t² − i²)/(i(2i + 1)).
// |b_i / b_{i−1}| < 1/2, so what is left after a term is below the term times
// (1 − d)/(1 + d): at d ≥ 0.95 the sum stops within 1e-16, in ≤ 12 terms.
constexpr double kSeriesMinCosine = 0.95;
constexpr int kSeriesTerms = 16;
constexpr std::array<double, kSeriesTerms + 1> kSeriesU = [] {
  std::array<double, kSeriesTerms + 1> u{};
  for (int i = 1; i <= kSeriesTerms; ++i) u[i] = 1.0 / (i * (2.0 * i + 1));
  return u;
}();
constexpr std::array<double, kSeriesTerms + 1> kSeriesV = [] {
  std::array<double, kSeriesTerms + 1> v{};
  for (int i = 1; i <= kSeriesTerms; ++i) v[i] = i / (2.0 * i + 1);
  return v;
}();

double SinRatio(double d, double t) {
  const double below = d - 1, t2 = t * t;
  double term = t, sum = t;
  for (int i = 1; i <= kSeriesTerms && std::abs(term) > 1e-17; ++i) {
    term *= (t2 * kSeriesU[i] - kSeriesV[i]) * below;
    sum += term;
  }
  return sum;
}

double WrapNear(double angle, double hint) {
  const double two_pi = 2.0 * std::numbers::pi;
  return angle + two_pi * std::round((hint - angle) / two_pi);
}

// Slerp without choosing the shorter arc. The angle comes from atan2 of the
// chord lengths, accurate at small angles where acos(dot) loses half its digits.
Eigen::Quaterniond SlerpNoFlip(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b, double t) {
  const double theta = 2.0 * std::atan2((a.coeffs() - b.coeffs()).norm(), (a.coeffs() + b.coeffs()).norm());
  const double s = std::sin(theta);
  if (theta < 1e-10) return Eigen::Quaterniond((a.coeffs() + t * (b.coeffs() - a.coeffs())).normalized());
  if (s < 1e-15) return a;  // b = −a: the same rotation
  const double wa = std::sin((1.0 - t) * theta) / s, wb = std::sin(t * theta) / s;
  return Eigen::Quaterniond(wa * a.coeffs() + wb * b.coeffs());
}

double AngularDistance(std::span<const double> a, std::span<const double> b) {
  double d = 0;
  for (size_t i = 0; i < a.size(); ++i) d += (a[i] - b[i]) * (a[i] - b[i]);
  return d;
}

}  // namespace

Eigen::Quaterniond AxisRotation(Axis axis, double angle) {
  return Eigen::Quaterniond(Eigen::AngleAxisd(angle, UnitAxis(axis)));
}

Eigen::Quaterniond EulerToQuaternion(std::span<const Axis> axes, std::span<const double> angles) {
  Eigen::Quaterniond q = Eigen::Quaterniond::Identity();
  for (size_t i = 0; i < axes.size() && i < angles.size(); ++i) q = q * AxisRotation(axes[i], angles[i]);
  return q.normalized();
}

bool QuaternionToEuler(const Eigen::Quaterniond& q, std::span<const Axis> axes, std::span<double> angles,
                       std::span<const double> hint) {
  std::fill(angles.begin(), angles.end(), 0.0);
  const size_t n = axes.size();
  if (n == 0) return true;
  const Eigen::Quaterniond qn = q.normalized();

  if (n == 1) {
    // Twist about the single axis.
    const int a = static_cast<int>(axes[0]);
    angles[0] = 2.0 * std::atan2(qn.vec()[a], qn.w());
    if (!hint.empty()) angles[0] = WrapNear(angles[0], hint[0]);
    return true;
  }

  // Two axes are decomposed as three with the missing axis as the last one;
  // its angle is ~0 when the rotation came from two channels.
  Axis a0 = axes[0], a1 = axes[1];
  Axis a2 = n >= 3 ? axes[2] : static_cast<Axis>(3 - static_cast<int>(a0) - static_cast<int>(a1));
  bool invertible = n <= 3 && a0 != a1 && a1 != a2;
  if (a0 == a1) a1 = static_cast<Axis>((static_cast<int>(a0) + 1) % 3);
  if (a1 == a2)
    a2 = static_cast<Axis>((static_cast<int>(a1) + 1) % 3 == static_cast<int>(a0) ? (static_cast<int>(a1) + 2) % 3
                                                                                  : (static_cast<int>(a1) + 1) % 3);

  const Eigen::Matrix3d r = qn.toRotationMatrix();
  const Eigen::Vector3d e = r.eulerAngles(static_cast<int>(a0), static_cast<int>(a1), static_cast<int>(a2));
  double s1[3] = {e[0], e[1], e[2]};
  // The other solution of the same rotation.
  double s2[3];
  if (a0 == a2) {  // proper Euler: (a+π, −b, c+π)
    s2[0] = e[0] + std::numbers::pi;
    s2[1] = -e[1];
    s2[2] = e[2] + std::numbers::pi;
  } else {  // Tait–Bryan: (a+π, π−b, c+π)
    s2[0] = e[0] + std::numbers::pi;
    s2[1] = std::numbers::pi - e[1];
    s2[2] = e[2] + std::numbers::pi;
  }
  const size_t m = std::min<size_t>(n, 3);
  double* best = s1;
  if (n == 2) {
    // Only the solution whose (dropped) third angle is ~0 reproduces the rotation.
    if (std::cos(s2[2]) > std::cos(s1[2])) best = s2;
    for (size_t i = 0; i < 2; ++i)
      best[i] = hint.size() > i ? WrapNear(best[i], hint[i]) : std::remainder(best[i], 2.0 * std::numbers::pi);
  } else if (!hint.empty()) {
    for (double* s : {s1, s2})
      for (size_t i = 0; i < 3 && i < hint.size(); ++i) s[i] = WrapNear(s[i], hint[i]);
    std::span<const double> h = hint.first(std::min(hint.size(), m));
    if (AngularDistance(std::span<const double>(s2, h.size()), h) <
        AngularDistance(std::span<const double>(s1, h.size()), h))
      best = s2;
  } else {
    for (double* s : {s1, s2})
      for (double& v : std::span<double>(s, 3)) v = std::remainder(v, 2.0 * std::numbers::pi);
    // Prefer the solution with the smallest middle angle magnitude.
    if (std::abs(s2[1]) < std::abs(s1[1]) - 1e-12) best = s2;
  }
  for (size_t i = 0; i < m; ++i) angles[i] = best[i];
  return invertible;
}

Eigen::Quaterniond ExpQuaternion(const Eigen::Vector3d& v) {
  const double theta = v.norm();
  if (theta < 1e-12) return Eigen::Quaterniond(1.0, 0.5 * v.x(), 0.5 * v.y(), 0.5 * v.z()).normalized();
  const Eigen::Vector3d axis = v / theta;
  const double s = std::sin(0.5 * theta);
  return Eigen::Quaterniond(std::cos(0.5 * theta), s * axis.x(), s * axis.y(), s * axis.z());
}

Eigen::Vector3d LogQuaternion(const Eigen::Quaterniond& q_in) {
  Eigen::Quaterniond q = q_in.normalized();
  if (q.w() < 0) q.coeffs() = -q.coeffs();  // angle in [0, π]
  const double s = q.vec().norm();
  if (s < 1e-12) return 2.0 * q.vec();
  const double theta = 2.0 * std::atan2(s, q.w());
  return q.vec() * (theta / s);
}

Eigen::Matrix3d ExpMatrix(const Eigen::Vector3d& v) {
  const double theta = v.norm();
  if (theta < 1e-12) return Eigen::Matrix3d::Identity();
  const Eigen::Vector3d u = v / theta;
  const double c = std::cos(theta), s = std::sin(theta), C = 1.0 - c;
  Eigen::Matrix3d r;
  r << c + u.x() * u.x() * C, u.x() * u.y() * C - u.z() * s, u.x() * u.z() * C + u.y() * s,
      u.y() * u.x() * C + u.z() * s, c + u.y() * u.y() * C, u.y() * u.z() * C - u.x() * s,
      u.z() * u.x() * C - u.y() * s, u.z() * u.y() * C + u.x() * s, c + u.z() * u.z() * C;
  return r;
}

Eigen::Vector3d LogMatrix(const Eigen::Matrix3d& r) {
  // Via the quaternion: stable near 0 and π, where the textbook
  // (R32−R23)/(2 sin θ) form divides by ~0.
  return LogQuaternion(Eigen::Quaterniond(r));
}

Eigen::Quaterniond SameHemisphere(const Eigen::Quaterniond& q, const Eigen::Quaterniond& reference) {
  return q.dot(reference) < 0 ? Eigen::Quaterniond(-q.coeffs()) : q;
}

Eigen::Quaterniond Slerp(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b, double t) {
  return SlerpNoFlip(a, SameHemisphere(b, a), t);
}

Eigen::Quaterniond SlerpFlat(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b_in, double t) {
  if (a.coeffs() == b_in.coeffs()) return a;
  Eigen::Vector4d b = b_in.coeffs();
  double dot = a.coeffs().dot(b);
  if (dot < 0) {
    b = -b;
    dot = -dot;
  }
  if (dot >= kSeriesMinCosine && dot < 0.9995 && t >= 0 && t <= 1) {
    const double wb = SinRatio(dot, t), wa = SinRatio(dot, 1 - t);
    return Eigen::Quaterniond(Eigen::Vector4d(wa * a.coeffs() + wb * b));
  }
  if (dot < 0.9995) {
    // sin((1−t)θ)/sin θ = cos tθ − cos θ · sin tθ / sin θ: one sin/cos pair
    // instead of three sines, the same weights.
    const double theta = std::acos(dot), sin = std::sqrt(1 - dot * dot);
    const double wb = std::sin(t * theta) / sin, wa = std::cos(t * theta) - dot * wb;
    return Eigen::Quaterniond(Eigen::Vector4d(wa * a.coeffs() + wb * b));
  }
  return Eigen::Quaterniond(((1 - t) * a.coeffs() + t * b).normalized());
}

Eigen::Matrix3d SlerpMatrix(const Eigen::Matrix3d& r1, const Eigen::Matrix3d& r2, double t) {
  return r1 * ExpMatrix(t * LogMatrix(r1.transpose() * r2));
}

Eigen::Quaterniond SquadControlPoint(const Eigen::Quaterniond& prev, const Eigen::Quaterniond& q_in,
                                     const Eigen::Quaterniond& next) {
  const Eigen::Quaterniond q = q_in.normalized();
  const Eigen::Quaterniond qi = q.conjugate();
  const Eigen::Quaterniond p = SameHemisphere(prev, q), n = SameHemisphere(next, q);
  // s = q · exp(−(log(q⁻¹·next) + log(q⁻¹·prev)) / 4), with log = half the rotation vector.
  const Eigen::Vector3d l = 0.5 * (LogQuaternion(qi * n) + LogQuaternion(qi * p));
  return (q * ExpQuaternion(-0.5 * l)).normalized();
}

Eigen::Quaterniond Squad(const Eigen::Quaterniond& q1, const Eigen::Quaterniond& s1, const Eigen::Quaterniond& s2,
                         const Eigen::Quaterniond& q2, double t) {
  // Unlike Slerp, the inner interpolations must not flip hemispheres
  // independently, or the spline loses C¹ continuity; callers pass keys
  // already aligned to one hemisphere.
  return SlerpNoFlip(SlerpNoFlip(q1, q2, t), SlerpNoFlip(s1, s2, t), 2.0 * t * (1.0 - t)).normalized();
}

void SquadControlPoints(const Eigen::Quaterniond& prev, const Eigen::Quaterniond& q_in, const Eigen::Quaterniond& next,
                        double dt_prev, double dt_next, Eigen::Quaterniond* s_in, Eigen::Quaterniond* s_out) {
  const Eigen::Quaterniond q = q_in.normalized();
  const Eigen::Quaterniond qi = q.conjugate();
  const bool has_prev = dt_prev > 0, has_next = dt_next > 0;
  // Rotation vectors from q to its neighbours, in q's frame.
  const Eigen::Vector3d lp = has_prev ? LogQuaternion(qi * prev) : Eigen::Vector3d::Zero();
  const Eigen::Vector3d ln = has_next ? LogQuaternion(qi * next) : Eigen::Vector3d::Zero();
  // Angular velocity at the key (rotation vector per second).
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  if (has_prev && has_next)
    w = (ln * (dt_prev / dt_next) - lp * (dt_next / dt_prev)) / (dt_prev + dt_next);
  else if (has_next)
    w = ln / dt_next;
  else if (has_prev)
    w = -lp / dt_prev;
  // Squad leaves a key with velocity log(q⁻¹q_next) + 2·log(q⁻¹s_out) per unit
  // of segment parameter and enters one with −log(q⁻¹q_prev) − 2·log(q⁻¹s_in);
  // solve both for the velocity w scaled by the segment's duration.
  if (s_out) *s_out = has_next ? (q * ExpQuaternion(0.5 * (dt_next * w - ln))).normalized() : q;
  if (s_in) *s_in = has_prev ? (q * ExpQuaternion(-0.5 * (dt_prev * w + lp))).normalized() : q;
}

Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& s) {
  // With S = UΣVᵀ the answer is R = V·Uᵀ, its last axis flipped if that
  // reflects. V and Σ² come from the symmetric eigenproblem of SᵀS (about
  // twice as fast as a 3×3 SVD, and this runs once per vertex per round),
  // uᵢ = S·vᵢ/σᵢ for the two largest σ, and the third axes as cross products,
  // which makes R a proper rotation by construction.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eigen(s.transpose() * s);
  const Eigen::Vector3d v1 = eigen.eigenvectors().col(2), v2 = eigen.eigenvectors().col(1);
  Eigen::Vector3d u1 = s * v1;
  const double n1 = u1.norm();
  if (!(n1 > 0)) return Eigen::Matrix3d::Identity();  // S = 0: every rotation is as good
  u1 /= n1;
  Eigen::Vector3d u2 = s * v2;
  u2 -= u2.dot(u1) * u1;
  const double n2 = u2.norm();
  u2 = n2 > 1e-12 * n1 ? Eigen::Vector3d(u2 / n2) : u1.unitOrthogonal();  // rank 1: any perpendicular
  return v1 * u1.transpose() + v2 * u2.transpose() + v1.cross(v2) * u1.cross(u2).transpose();
}

}  // namespace armature
