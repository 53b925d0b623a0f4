// Internal: three.js's Quaternion.slerpFlat (SlerpFlat, math/rotation.h) on
// four pairs at once in float, for the motion blend's float lanes. Below a
// 0.9995 cosine the weights sin(tθ)/sin θ and sin((1−t)θ)/sin θ come from
// Eberly's series ("A Fast and Accurate Algorithm for Computing SLERP",
// 2011) instead of acos and sin: no libm call, no branch. Above it, lerp then
// normalize, as three.js.
//
// The series: sin(tθ)/sin θ = Σ b_i (cos θ − 1)^i, with b_0 = t and
// b_i = b_{i−1}·(t² − i²)/(i(2i + 1)); its terms shrink about as
// ((1 − cos θ)/2)^i, so the four lanes' smallest cosine picks how many are
// summed: 4 from 0.9, 8 from 0.5, else 16, the last scaled by μ (Eberly's
// correction for the tail, chosen to minimize the worst error over the
// tier's cosines up to 0.9995 and t in [0, 1]). In exact arithmetic the
// worst errors are 4.6e-9, 2.0e-8 and 3.2e-8; evaluated in float, about
// 1.4e-7 (tests/engine/anim/motion_float_blend_test.cc bounds the blend).
#pragma once

#include <algorithm>

#include "anim/compression/simd4.h"

namespace armature::motion_internal {

using compression_internal::Load4;
using compression_internal::Select;
using compression_internal::Splat;
using compression_internal::Sqrt;
using compression_internal::v4;
using compression_internal::v4i;

// sin(tθ)/sin θ for cos θ = x and t in [0, 1], per lane, by `kTerms` terms
// of the series (the last scaled by `mu`).
template <int kTerms>
inline v4 SinRatio4(v4 x, v4 t, double mu) {
  const v4 xm1 = x - Splat(1.f), tt = t * t;
  v4 r = Splat(1.f);
  for (int i = kTerms; i >= 1; --i) {
    const double scale = i == kTerms ? mu : 1.0;
    const float u = static_cast<float>(scale / (i * (2.0 * i + 1))), v = static_cast<float>(scale * i / (2.0 * i + 1));
    r = Splat(1.f) + (Splat(u) * tt - Splat(v)) * xm1 * r;
  }
  return t * r;
}

// The pair of weights sin((1−t)θ)/sin θ and sin(tθ)/sin θ, as many terms
// as the lanes' smallest cosine needs.
inline void SineWeights4(v4 x, v4 s, v4 t, v4& wa, v4& wb) {
  const float least = std::min(std::min(x[0], x[1]), std::min(x[2], x[3]));
  if (least >= 0.9f) {
    wa = SinRatio4<4>(x, s, 1.05), wb = SinRatio4<4>(x, t, 1.05);
  } else if (least >= 0.5f) {
    wa = SinRatio4<8>(x, s, 1.3), wb = SinRatio4<8>(x, t, 1.3);
  } else {
    wa = SinRatio4<16>(x, s, 1.92), wb = SinRatio4<16>(x, t, 1.92);
  }
}

// slerpFlat(a, b, t) per lane: quaternions as four vectors (x y z w), t in [0, 1].
inline void SlerpFlat4(const v4 a[4], const v4 b_in[4], v4 t, v4 out[4]) {
  v4 d = a[0] * b_in[0] + a[1] * b_in[1] + a[2] * b_in[2] + a[3] * b_in[3];
  const v4i flip = d < Splat(0.f);
  v4 b[4];
  for (int c = 0; c < 4; ++c) b[c] = Select(flip, -b_in[c], b_in[c]);
  d = Select(flip, -d, d);
  // Near each other (a cosine from 0.9995) the lerp's weights, then
  // normalized; otherwise the sine weights. Each only when a lane needs it.
  const v4 s = Splat(1.f) - t;
  const v4i near = d >= Splat(0.9995f);
  const bool any_near = (near[0] | near[1] | near[2] | near[3]) != 0;
  const bool all_near = (near[0] & near[1] & near[2] & near[3]) != 0;
  v4 wa = s, wb = t;
  if (!all_near) {
    v4 sine_a, sine_b;  // the lanes that lerp count as 0.9995: these weights are not theirs
    SineWeights4(Select(near, Splat(0.9995f), d), s, t, sine_a, sine_b);
    wa = Select(near, s, sine_a), wb = Select(near, t, sine_b);
  }
  for (int c = 0; c < 4; ++c) out[c] = wa * a[c] + wb * b[c];
  if (!any_near) return;
  const v4 inverse_norm = Splat(1.f) / Sqrt(out[0] * out[0] + out[1] * out[1] + out[2] * out[2] + out[3] * out[3]);
  for (int c = 0; c < 4; ++c) out[c] = Select(near, out[c] * inverse_norm, out[c]);
}

}  // namespace armature::motion_internal
