// Internal: slerp without trigonometry, four quaternions per vector (GCC and
// Clang vector extensions: SSE2 on x86-64, NEON elsewhere), for compiled clips.
//
// slerp(a, b, t) = w(1−t, x)·a + w(t, x)·b with x = a·b = cos θ and
// w(t, x) = sin(tθ)/sin θ. Eberly ("A Fast and Accurate Algorithm for
// Computing SLERP", 2011) writes w as a power series in (x − 1):
//   w = Σ c_i,  c_0 = t,  c_i = c_{i−1} · (t² − i²) / (i(2i + 1)) · (x − 1).
// The series converges slowly near θ = 90°, so the arc is first halved: the
// unit midpoint m = (a + b)/|a + b| splits it into two arcs of θ/2 ≤ 45°
// (cos ≥ 0.707), and the half that holds t is interpolated with 6 terms, the
// last scaled by 1 + μ to absorb the truncated tail. Over every pair of unit
// quaternions and t ∈ [0, 1] the rotation differs from the exact slerp by at
// most 4e-9 rad in exact arithmetic; in float the keys' own rounding
// dominates (≈1e-7 rad). CompiledClipTest.FastSlerpIsWithinTheStatedBound
// checks 1e-6 rad. Like slerp the speed is constant in t (no nlerp drift).
#pragma once

#include <cstddef>

#if defined(__SSE__)
#include <immintrin.h>
#endif

namespace armature::compiled_internal {

using v4 = float __attribute__((vector_size(16)));
using v4i = int __attribute__((vector_size(16)));

inline v4 Splat(float f) { return v4{f, f, f, f}; }

inline v4 Load4(const float* p) {
  v4 r;
  __builtin_memcpy(&r, p, sizeof r);
  return r;
}

inline v4 Select(v4i mask, v4 yes, v4 no) { return mask ? yes : no; }

inline v4 Max(v4 x, v4 y) { return Select(x > y, x, y); }

inline v4 Sqrt(v4 x) {
#if defined(__SSE__)
  return _mm_sqrt_ps(x);
#else
  v4 r = x;
  for (int i = 0; i < 4; ++i) r[i] = __builtin_sqrtf(x[i]);
  return r;
#endif
}

// sin(tθ)/sin θ from x − 1 = cos θ − 1 (θ ≤ 45°) and t, t² per lane. The
// term ratios are independent, so only one multiply per term is serial.
inline v4 SlerpWeight(v4 t, v4 t2, v4 xm1) {
  constexpr float kOnePlusMu = 1.1525f;
  const v4 f1 = (Splat(1.f / 3) * t2 - Splat(1.f / 3)) * xm1;
  const v4 f2 = (Splat(1.f / 10) * t2 - Splat(2.f / 5)) * xm1;
  const v4 f3 = (Splat(1.f / 21) * t2 - Splat(3.f / 7)) * xm1;
  const v4 f4 = (Splat(1.f / 36) * t2 - Splat(4.f / 9)) * xm1;
  const v4 f5 = (Splat(1.f / 55) * t2 - Splat(5.f / 11)) * xm1;
  const v4 f6 = (Splat(kOnePlusMu / 78) * t2 - Splat(kOnePlusMu * 6 / 13)) * xm1;
  const v4 c1 = t * f1, c2 = c1 * f2, c3 = c2 * f3, c4 = c3 * f4, c5 = c4 * f5, c6 = c5 * f6;
  return ((t + c1) + (c2 + c3)) + ((c4 + c5) + c6);
}

// Replaces the arc p → q (cos = d ≥ −1, per lane) by the half that holds
// parameter s, rescaling s to it; returns the new arc's cosine.
inline v4 HalveArc(v4 p[4], v4 q[4], v4& s, v4 d) {
  // m = (p + q)/|p + q|, |p + q| = √(2 + 2d); p·m = cos(θ/2) = (1 + d)/|p + q|.
  const v4 inv = Splat(1.f) / Sqrt(Max(Splat(2.f) + Splat(2.f) * d, Splat(1e-30f)));
  const v4i low = s < Splat(0.5f);
  for (int c = 0; c < 4; ++c) {
    const v4 m = (p[c] + q[c]) * inv;
    p[c] = Select(low, p[c], m);
    q[c] = Select(low, m, q[c]);
  }
  s = Select(low, s + s, s + s - Splat(1.f));
  return (Splat(1.f) + d) * inv;
}

// Four slerps, SoA: a[c], b[c] are component c (x, y, z, w) of four unit
// quaternions; u is each lane's parameter in [0, 1]. kShortest: along the
// shorter arc, the result in a's hemisphere (Slerp in math/rotation.h);
// otherwise along the arc as given (squad's inner slerps), halved twice so
// arcs up to 180° stay within the series' 45°. The result is unit length
// (normalized along the given arc).
template <bool kShortest>
inline void Slerp4(const v4 a[4], const v4 b[4], v4 u, v4 out[4]) {
  v4 d = a[0] * b[0] + a[1] * b[1] + a[2] * b[2] + a[3] * b[3];
  v4 p[4], q[4];
  const v4 sign = kShortest ? Select(d < Splat(0.f), Splat(-1.f), Splat(1.f)) : Splat(1.f);
  d *= sign;
  for (int c = 0; c < 4; ++c) {
    p[c] = a[c];
    q[c] = b[c] * sign;
  }
  v4 s = u;
  v4 x = HalveArc(p, q, s, d);
  if (!kShortest) x = HalveArc(p, q, s, x);
  const v4 xm1 = x - Splat(1.f), s1 = Splat(1.f) - s;
  const v4 w_end = SlerpWeight(s, s * s, xm1), w_start = SlerpWeight(s1, s1 * s1, xm1);
  for (int c = 0; c < 4; ++c) out[c] = w_start * p[c] + w_end * q[c];
  if (kShortest) return;  // unit to float precision: unit keys, |a + b| ≥ √2, weights exact to 4e-9
  // Along the given arc |a + b| can vanish and the midpoint lose its length.
  const v4 n = Splat(1.f) / Sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] + out[3] * out[3]);
  for (int c = 0; c < 4; ++c) out[c] *= n;
}

}  // namespace armature::compiled_internal
