// Internal: four floats per vector (GCC and Clang vector extensions: SSE2 on
// x86-64, NEON elsewhere), for the sampling job's rotations.
#pragma once

#include <cstddef>
#include <cstdint>

#if defined(__SSE2__)
#include <immintrin.h>
#endif

namespace armature::compression_internal {

// The sampling job's decode path, inlined even where GCC would not: its AVX2
// clone (clip_sampling_job.cc) is only as fast as what is inlined into it,
// and an inlined copy is the only AVX2 copy there is (no out-of-line one
// that the linker could pick for another caller on a CPU without AVX2).
#define ARMATURE_DECODE_INLINE [[gnu::always_inline]] inline

using v4 = float __attribute__((vector_size(16)));
using v4i = int __attribute__((vector_size(16)));

inline v4 Splat(float f) { return v4{f, f, f, f}; }

inline v4 Load4(const float* p) {
  v4 r;
  __builtin_memcpy(&r, p, sizeof r);
  return r;
}

inline void Store4(float* p, v4 x) { __builtin_memcpy(p, &x, sizeof x); }

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

// 1/√x to about 12 bits (a Newton step makes it about 23).
inline v4 InverseSqrtEstimate(v4 x) {
#if defined(__SSE__)
  return _mm_rsqrt_ps(x);
#else
  return Splat(1.f) / Sqrt(x);
#endif
}

// Rows to columns: r[i][c] becomes r[c][i].
inline void Transpose(v4 r[4]) {
#if defined(__SSE__)
  _MM_TRANSPOSE4_PS(r[0], r[1], r[2], r[3]);
#else
  v4 t[4];
  for (int i = 0; i < 4; ++i)
    for (int c = 0; c < 4; ++c) t[c][i] = r[i][c];
  for (int i = 0; i < 4; ++i) r[i] = t[i];
#endif
}

// q (x y z w, float) to double, times s = ½(3 − |q|²) in double: one Newton
// step toward 1/|q|, stored as x y z w. |q|² is summed as Eigen sums a
// Quaterniond's coefficients on SSE2, (x² + z²) + (y² + w²), so the result
// is Eigen's `q.coeffs() *= 0.5 * (3.0 - q.squaredNorm())` bit for bit.
inline void StoreUnitDouble(v4 q, double* out) {
#if defined(__SSE2__)
  const __m128d lo = _mm_cvtps_pd(q), hi = _mm_cvtps_pd(_mm_movehl_ps(q, q));
  const __m128d halves = _mm_add_pd(_mm_mul_pd(lo, lo), _mm_mul_pd(hi, hi));
  const __m128d n = _mm_add_sd(halves, _mm_unpackhi_pd(halves, halves));
  __m128d s = _mm_mul_sd(_mm_set_sd(0.5), _mm_sub_sd(_mm_set_sd(3.0), n));
  s = _mm_unpacklo_pd(s, s);
  _mm_storeu_pd(out, _mm_mul_pd(lo, s));
  _mm_storeu_pd(out + 2, _mm_mul_pd(hi, s));
#else
  double d[4] = {q[0], q[1], q[2], q[3]};
  const double s = 0.5 * (3.0 - ((d[0] * d[0] + d[2] * d[2]) + (d[1] * d[1] + d[3] * d[3])));
  for (int c = 0; c < 4; ++c) out[c] = d[c] * s;
#endif
}

}  // namespace armature::compression_internal
