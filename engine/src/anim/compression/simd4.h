// Internal: four floats per vector (GCC and Clang vector extensions: SSE2 on
// x86-64, NEON elsewhere), for the sampling job's rotations.
#pragma once

#include <cstddef>

#if defined(__SSE__)
#include <immintrin.h>
#endif

namespace armature::compression_internal {

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

// 1/√x to about 12 bits (a Newton step makes it about 23).
inline v4 InverseSqrtEstimate(v4 x) {
#if defined(__SSE__)
  return _mm_rsqrt_ps(x);
#else
  return Splat(1.f) / Sqrt(x);
#endif
}

}  // namespace armature::compression_internal
