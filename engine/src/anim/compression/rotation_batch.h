// Internal: the sampling job's rotations, four tracks per vector. Each lane
// holds a track's two samples as kept (three components, the fourth rebuilt
// as √(1 − a² − b² − c²)) and its parameter; nlerp is the same in any
// component order, so the rebuilt one is put back in its place on store.
// Samples arrive as rows (x y z of one track) and are transposed in
// registers: scalar stores read back as a vector stall on store forwarding.
#pragma once

#include <cstddef>
#include <type_traits>

#include "anim/compression/simd4.h"
#include "armature/engine/math/transform.h"

namespace armature::compression_internal {

// Unit in double, as the stored rotations are: float samples leave |q| − 1
// near 1e-7, which rotation matrices (ComputeWorld) and quaternion products
// (IK) would turn into different floats. One Newton step toward 1/|q| (no
// sqrt, no division) takes it to about 1e-14.
inline void MakeUnit(Eigen::Quaterniond& q) { q.coeffs() *= 0.5 * (3.0 - q.squaredNorm()); }

// `Out`: Trs (its rotation, made unit in double) or float (x y z w, unit in
// float: the crowd's float32 wire needs no more).
template <class Out>
class RotationBatchOf {
 public:
  // Lanes left unset (Add writes them before Flush reads them): a sink
  // holds one per call, and zeroing them was a `rep stos` every call.
  RotationBatchOf() {}

  // `a`, `b`: the kept components in lanes 0–2 (lane 3 is ignored).
  void Add(v4 a, v4 b, float u, int dropped, Out* out) {
    a[3] = u;  // rides in the free lane: transposed with the samples, no scalar store to reload
    a_[n_] = a;
    b_[n_] = b;
    dropped_[n_] = dropped;
    out_[n_] = out;
    if (++n_ == 4) Flush();
  }
  void Add(const float* a, const float* b, float u, int dropped, Out* out) {
    Add(v4{a[0], a[1], a[2], 0.f}, v4{b[0], b[1], b[2], 0.f}, u, dropped, out);
  }

  ARMATURE_DECODE_INLINE void Flush() {
    if (n_ == 0) return;
    for (size_t lane = n_; lane < 4; ++lane) a_[lane] = b_[lane] = Splat(0.f);  // unused lanes: identity
    Transpose(a_);
    Transpose(b_);
    const v4 zero = Splat(0.f), one = Splat(1.f), u = a_[3];
    const v4 wa = Sqrt(Max(one - a_[0] * a_[0] - a_[1] * a_[1] - a_[2] * a_[2], zero));
    const v4 wb = Sqrt(Max(one - b_[0] * b_[0] - b_[1] * b_[1] - b_[2] * b_[2], zero));
    const v4 d = a_[0] * b_[0] + a_[1] * b_[1] + a_[2] * b_[2] + wa * wb;
    const v4 ub = Select(d < zero, -u, u), ua = one - u;
    v4 r[4];
    for (int c = 0; c < 3; ++c) r[c] = ua * a_[c] + ub * b_[c];
    r[3] = ua * wa + ub * wb;
    const v4 norm2 = r[0] * r[0] + r[1] * r[1] + r[2] * r[2] + r[3] * r[3];
    v4 inv;
    if constexpr (std::is_same_v<Out, float>) {  // float lanes: an estimate and one Newton step (|q| − 1 < 1e-6)
      const v4 e = InverseSqrtEstimate(norm2);
      inv = e * (Splat(1.5f) - Splat(0.5f) * norm2 * e * e);
    } else {
      inv = one / Sqrt(norm2);
    }
    for (int c = 0; c < 4; ++c) r[c] *= inv;
    Transpose(r);  // r[lane]: kept components, then the rebuilt one
    for (size_t lane = 0; lane < n_; ++lane) {
      v4 q = r[lane];
      if (dropped_[lane] != 3) {  // put the rebuilt component back in its place
        for (int c = 0, k = 0; c < 4; ++c) q[c] = c == dropped_[lane] ? r[lane][3] : r[lane][k++];
      }
      if constexpr (std::is_same_v<Out, float>) {
        Store4(out_[lane], q);
      } else {
        StoreUnitDouble(q, out_[lane]->rotation.coeffs().data());
      }
    }
    n_ = 0;
  }

 private:
  v4 a_[4], b_[4];  // rows, then (after Transpose) components; a_'s fourth: the parameters
  int dropped_[4];
  Out* out_[4];
  size_t n_ = 0;
};

using RotationBatch = RotationBatchOf<Trs>;

}  // namespace armature::compression_internal
