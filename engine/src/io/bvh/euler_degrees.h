// Euler angles in degrees → quaternion for the BVH reader's frame loop, where
// libm's sincos calls were most of the parse time. The sine and cosine are
// fdlibm's kernels inlined (range reduction by π/2 in two parts, degree-13
// and degree-14 polynomials on [−π/4, π/4], with the reduction's tail): at
// most 1 ulp from the exact values, so the quaternion is within 1e-15 of
// EulerToQuaternion's (tests/engine/io/bvh_frame_values_test.cc).
#pragma once

#include <cmath>
#include <cstddef>
#include <numbers>

#include <Eigen/Geometry>

#include "armature/engine/math/rotation.h"

namespace armature::bvh_detail {

// sin and cos of `x`, for |x| below 1e6 (a larger angle takes libm's).
inline void SinCos(double x, double* sin_out, double* cos_out) {
  if (!(std::fabs(x) < 1e6)) {
    *sin_out = std::sin(x);
    *cos_out = std::cos(x);
    return;
  }
  constexpr double kTwoOverPi = 6.36619772367581382433e-01;
  constexpr double kPiOver2Hi = 1.57079632673412561417e+00;  // first 33 bits of π/2: k·hi is exact
  constexpr double kPiOver2Lo = 6.07710050650619224932e-11;  // π/2 − hi
  constexpr double kRound = 6755399441055744.0;              // 1.5·2^52: adding it rounds to an integer
  const double k = (x * kTwoOverPi + kRound) - kRound;
  const double r0 = x - k * kPiOver2Hi;
  const double w = k * kPiOver2Lo;
  const double y = r0 - w;             // reduced argument, |y| <= π/4 (a hair more)
  const double y_tail = (r0 - y) - w;  // what y lost to rounding

  const double z = y * y;
  // fdlibm __kernel_sin(y, y_tail, 1)
  constexpr double S1 = -1.66666666666666324348e-01, S2 = 8.33333333332248946124e-03, S3 = -1.98412698298579493134e-04,
                   S4 = 2.75573137070700676789e-06, S5 = -2.50507602534068634195e-08, S6 = 1.58969099521155010221e-10;
  const double v = z * y;
  const double rs = S2 + z * (S3 + z * (S4 + z * (S5 + z * S6)));
  const double s = y - ((z * (0.5 * y_tail - v * rs) - y_tail) - v * S1);
  // fdlibm __kernel_cos(y, y_tail)
  constexpr double C1 = 4.16666666666666019037e-02, C2 = -1.38888888888741095749e-03, C3 = 2.48015872894767294178e-05,
                   C4 = -2.75573143513906633035e-07, C5 = 2.08757232129817482790e-09, C6 = -1.13596475577881948265e-11;
  const double rc = z * (C1 + z * (C2 + z * (C3 + z * (C4 + z * (C5 + z * C6)))));
  const double hz = 0.5 * z;
  const double one_minus_hz = 1.0 - hz;
  const double c = one_minus_hz + (((1.0 - one_minus_hz) - hz) + (z * rc - y * y_tail));

  switch (static_cast<long long>(k) & 3) {
    case 0:
      *sin_out = s;
      *cos_out = c;
      break;
    case 1:
      *sin_out = c;
      *cos_out = -s;
      break;
    case 2:
      *sin_out = -s;
      *cos_out = -c;
      break;
    default:
      *sin_out = -c;
      *cos_out = s;
      break;
  }
}

// The rotation of `count` channels about `axes`, angles `degrees[columns[i]]`,
// composed in order (as EulerToQuaternion), normalized. Scalar products on
// purpose: Eigen's SSE quaternion product goes through memory, and writing a
// quaternion in halves then reading it whole stalls store forwarding.
inline Eigen::Quaterniond EulerDegreesToQuaternion(const Axis* axes, const int* columns, size_t count,
                                                   const double* degrees) {
  constexpr double kHalfDegree = std::numbers::pi / 360.0;
  double w = 1, x = 0, y = 0, z = 0;
  for (size_t i = 0; i < count; ++i) {
    double s = 0, c = 1;
    SinCos(degrees[columns[i]] * kHalfDegree, &s, &c);
    const int a = static_cast<int>(axes[i]);
    const double ex = a == 0 ? s : 0.0, ey = a == 1 ? s : 0.0, ez = a == 2 ? s : 0.0;
    const double nw = w * c - x * ex - y * ey - z * ez;
    const double nx = w * ex + x * c + y * ez - z * ey;
    const double ny = w * ey - x * ez + y * c + z * ex;
    const double nz = w * ez + x * ey - y * ex + z * c;
    w = nw;
    x = nx;
    y = ny;
    z = nz;
  }
  // A product of unit quaternions: |q|² = 1 + e with e of a few ulps, so one
  // Newton step from 1, 1/|q| ≈ 1.5 − |q|²/2, is off by 3e²/8 (~1e-31).
  const double inverse_norm = 1.5 - 0.5 * (w * w + x * x + y * y + z * z);
  return Eigen::Quaterniond(w * inverse_norm, x * inverse_norm, y * inverse_norm, z * inverse_norm);
}

}  // namespace armature::bvh_detail
