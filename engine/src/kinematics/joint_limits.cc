#include "armature/engine/kinematics/joint_limits.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <string>

namespace armature {
namespace {

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

std::string Num(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// [lo, hi] in degrees for `field`.`lo_name`/`hi_name` (with "[index]" when
// index ≥ 0). Messages are only built on failure: this runs per request.
Status CheckRange(double lo, double hi, std::string_view field, const char* lo_name, const char* hi_name, int index) {
  auto name = [&](const char* n) {
    std::string s(n);
    if (index >= 0) s += '[' + std::to_string(index) + ']';
    return s;
  };
  auto fail = [&](const char* n, const std::string& what) {
    return Status::InvalidArgument(std::string(field) + "." + name(n) + what);
  };
  if (!std::isfinite(lo)) return fail(lo_name, ": not finite");
  if (!std::isfinite(hi)) return fail(hi_name, ": not finite");
  if (lo > hi) return fail(lo_name, " > " + name(hi_name) + " (" + Num(lo) + " > " + Num(hi) + ")");
  if (lo < -360.0) return fail(lo_name, ": below -360 (" + Num(lo) + ")");
  if (hi > 360.0) return fail(hi_name, ": above 360 (" + Num(hi) + ")");
  if (hi - lo > 360.0) return fail(lo_name, ".." + name(hi_name) + ": a range wider than 360 degrees");
  return Status::Ok();
}

}  // namespace

double ClampAngle(double angle, double lo, double hi) {
  double best = angle, best_distance = INFINITY;
  for (int k : {0, -1, 1, -2, 2}) {
    const double a = angle + k * kTwoPi;
    const double d = a < lo ? lo - a : (a > hi ? a - hi : 0.0);
    if (d < best_distance) best = a, best_distance = d;
  }
  return std::clamp(best, lo, hi);
}

namespace {

double AngleDistance(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return 2.0 * std::acos(std::min(1.0, std::abs(a.dot(b))));
}

// Any unit vector perpendicular to unit `a`.
Eigen::Vector3d Perpendicular(const Eigen::Vector3d& a) {
  const Eigen::Vector3d other = std::abs(a.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY();
  return a.cross(other).normalized();
}

}  // namespace

Status ValidateJointLimit(const JointLimit& limit, std::string_view field) {
  auto fail = [&](const char* what) { return Status::InvalidArgument(std::string(field) + what); };
  if (limit.kind == JointLimit::Kind::kEuler) {
    if (limit.order[0] == limit.order[1] || limit.order[1] == limit.order[2])
      return fail(".order: neighbouring axes must differ");
    const Eigen::Array3d lo = limit.min_deg.array(), hi = limit.max_deg.array();
    if ((lo <= hi).all() && (lo >= -360.0).all() && (hi <= 360.0).all() && (hi - lo <= 360.0).all())
      return Status::Ok();  // the common case, without building messages (NaN fails every comparison)
    for (int i = 0; i < 3; ++i)
      ARMATURE_RETURN_IF_ERROR(CheckRange(limit.min_deg[i], limit.max_deg[i], field, "min_deg", "max_deg", i));
    return Status::Ok();
  }
  if (!limit.axis.allFinite() || limit.axis.norm() < 1e-12) return fail(".axis: zero length or not finite");
  if (!std::isfinite(limit.cone_deg)) return fail(".cone_deg: not finite");
  if (limit.cone_deg < 0)
    return Status::InvalidArgument(std::string(field) + ".cone_deg: negative (" + Num(limit.cone_deg) + ")");
  if (limit.cone_deg > 180)
    return Status::InvalidArgument(std::string(field) + ".cone_deg: above 180 (" + Num(limit.cone_deg) + ")");
  const double lo = limit.twist_min_deg, hi = limit.twist_max_deg;
  if (lo <= hi && lo >= -360.0 && hi <= 360.0 && hi - lo <= 360.0) return Status::Ok();
  return CheckRange(lo, hi, field, "twist_min_deg", "twist_max_deg", -1);
}

SwingTwist DecomposeSwingTwist(const Eigen::Quaterniond& delta, const Eigen::Vector3d& unit_axis) {
  const Eigen::Quaterniond q = delta.normalized();
  SwingTwist st;
  const double along = q.vec().dot(unit_axis);
  const double norm = std::hypot(q.w(), along);
  if (norm < 1e-12) {  // a half turn about an axis perpendicular to `unit_axis`: no twist
    st.twist = Eigen::Quaterniond::Identity();
  } else {
    const double sign = q.w() < 0 ? -1.0 : 1.0;  // w ≥ 0 keeps the twist angle in [−π, π]
    st.twist = Eigen::Quaterniond(sign * q.w() / norm, sign * along / norm * unit_axis.x(),
                                  sign * along / norm * unit_axis.y(), sign * along / norm * unit_axis.z());
  }
  st.twist_angle = 2.0 * std::atan2(st.twist.vec().dot(unit_axis), st.twist.w());
  st.swing = q * st.twist.conjugate();
  st.swing_angle = 2.0 * std::acos(std::min(1.0, std::abs(st.swing.w())));
  return st;
}

namespace {

// ClampedEulerAngles, telling whether Δ was inside already.
Eigen::Vector3d ClampEuler(const JointLimit& limit, const Eigen::Quaterniond& delta, bool* inside) {
  const Eigen::Vector3d lo = limit.min_deg * kDegToRad, hi = limit.max_deg * kDegToRad;
  double first[3];
  QuaternionToEuler(delta, limit.order, first);
  *inside = lo[0] <= first[0] && first[0] <= hi[0] && lo[1] <= first[1] && first[1] <= hi[1] && lo[2] <= first[2] &&
            first[2] <= hi[2];
  if (*inside) return {first[0], first[1], first[2]};  // nothing to choose
  // The other solution of the same rotation (see QuaternionToEuler).
  const bool proper = limit.order[0] == limit.order[2];
  const double second[3] = {first[0] + std::numbers::pi, proper ? -first[1] : std::numbers::pi - first[1],
                            first[2] + std::numbers::pi};
  Eigen::Vector3d best = Eigen::Vector3d::Zero();
  double best_distance = INFINITY;
  auto consider = [&](const Eigen::Vector3d& a) {
    const std::array<double, 3> angles = {a[0], a[1], a[2]};
    const double d = AngleDistance(EulerToQuaternion(limit.order, angles), delta);
    if (d < best_distance - 1e-12) best = a, best_distance = d;
  };
  for (const double* s : {static_cast<const double*>(first), static_cast<const double*>(second)}) {
    Eigen::Vector3d a;
    for (int i = 0; i < 3; ++i) a[i] = ClampAngle(s[i], lo[i], hi[i]);
    consider(a);
  }
  // In gimbal lock (middle ±90° for Tait–Bryan, 0° or 180° for proper Euler)
  // only a0 + k·a2 matters: an in-range pair may exist though neither
  // textbook solution is in range (a shoulder held at its −90° bound).
  const Axis a0 = limit.order[0], a1 = limit.order[1], a2 = limit.order[2];
  const double pi = std::numbers::pi;
  for (double b : proper ? std::array<double, 2>{0.0, pi} : std::array<double, 2>{-pi / 2, pi / 2}) {
    const double middle = ClampAngle(b, lo[1], hi[1]);
    if (std::abs(std::remainder(middle - b, kTwoPi)) > 1e-12 || std::abs(std::remainder(first[1] - b, kTwoPi)) > 1e-3)
      continue;
    const Eigen::Quaterniond rb = AxisRotation(a1, middle);
    const Eigen::Quaterniond about_a0 = delta * rb.conjugate();
    const double theta = 2.0 * std::atan2(about_a0.vec()[static_cast<int>(a0)], about_a0.w());
    // R_b·R_c(x) = R_a(k·x)·R_b at the lock.
    const double k = AngleDistance(rb * AxisRotation(a2, 0.5), AxisRotation(a0, 0.5) * rb) < 1e-6 ? 1.0 : -1.0;
    for (int turn = -1; turn <= 1; ++turn) {
      const double t = theta + turn * kTwoPi;  // a0 + k·a2 = t
      const double from = std::max(lo[0], k > 0 ? t - hi[2] : t + lo[2]);
      const double to = std::min(hi[0], k > 0 ? t - lo[2] : t + hi[2]);
      if (from > to) continue;
      const double x = std::clamp(first[0], from, to);
      consider(Eigen::Vector3d(x, middle, k * (t - x)));
    }
  }
  return best;
}

}  // namespace

Eigen::Vector3d ClampedEulerAngles(const JointLimit& limit, const Eigen::Quaterniond& delta) {
  bool inside;
  return ClampEuler(limit, delta, &inside);
}

Eigen::Quaterniond ProjectToLimit(const JointLimit& limit, const Eigen::Quaterniond& delta) {
  if (limit.kind == JointLimit::Kind::kEuler) {
    bool inside;
    const Eigen::Vector3d a = ClampEuler(limit, delta, &inside);
    if (inside) return delta;
    const std::array<double, 3> angles = {a[0], a[1], a[2]};
    return SameHemisphere(EulerToQuaternion(limit.order, angles), delta);
  }
  const Eigen::Vector3d axis = limit.axis.normalized();
  // Inside? cos(swing/2) = |(w, v·axis)| for a unit Δ; the twist angle is
  // only needed for a bounded twist. (This runs after every solver step.)
  const double along = delta.vec().dot(axis);
  if (std::hypot(delta.w(), along) >= std::cos(0.5 * limit.cone_deg * kDegToRad)) {
    if (limit.twist_max_deg - limit.twist_min_deg >= 360.0) return delta;
    const double t = 2.0 * std::atan2(delta.w() < 0 ? -along : along, std::abs(delta.w()));
    const double lo = limit.twist_min_deg * kDegToRad, hi = limit.twist_max_deg * kDegToRad;
    if (std::abs(std::remainder(ClampAngle(t, lo, hi) - t, kTwoPi)) < 1e-15) return delta;
  }
  const SwingTwist st = DecomposeSwingTwist(delta, axis);
  const double twist = ClampAngle(st.twist_angle, limit.twist_min_deg * kDegToRad, limit.twist_max_deg * kDegToRad);
  Eigen::Quaterniond swing = st.swing;
  const double cone = limit.cone_deg * kDegToRad;
  if (st.swing_angle > cone) {
    const Eigen::Vector3d v = LogQuaternion(st.swing);  // angle ∈ [0, π], axis ⊥ `axis`
    swing = v.norm() > 1e-12 ? ExpQuaternion(v * (cone / v.norm())) : Eigen::Quaterniond::Identity();
  }
  return SameHemisphere(swing * Eigen::Quaterniond(Eigen::AngleAxisd(twist, axis)), delta);
}

bool WithinLimit(const JointLimit& limit, const Eigen::Quaterniond& delta, double slack_rad) {
  return AngleDistance(ProjectToLimit(limit, delta), delta) <= slack_rad;
}

Eigen::Quaterniond SampleWithinLimit(const JointLimit& limit, const Eigen::Vector3d& u) {
  if (limit.kind == JointLimit::Kind::kEuler) {
    std::array<double, 3> angles;
    for (int i = 0; i < 3; ++i)
      angles[i] = (limit.min_deg[i] + u[i] * (limit.max_deg[i] - limit.min_deg[i])) * kDegToRad;
    return EulerToQuaternion(limit.order, angles);
  }
  const Eigen::Vector3d axis = limit.axis.normalized();
  const Eigen::Vector3d e1 = Perpendicular(axis), e2 = axis.cross(e1);
  const double phi = kTwoPi * u[0];
  const double swing = limit.cone_deg * kDegToRad * std::sqrt(u[1]);
  const double twist = (limit.twist_min_deg + u[2] * (limit.twist_max_deg - limit.twist_min_deg)) * kDegToRad;
  const Eigen::Vector3d swing_axis = std::cos(phi) * e1 + std::sin(phi) * e2;
  return Eigen::Quaterniond(Eigen::AngleAxisd(swing, swing_axis)) * Eigen::Quaterniond(Eigen::AngleAxisd(twist, axis));
}

}  // namespace armature
