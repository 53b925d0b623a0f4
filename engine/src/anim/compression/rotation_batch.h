// Internal: the sampling job's rotations, four tracks per vector. Each lane
// holds a track's two samples as kept (three components, the fourth rebuilt
// as √(1 − a² − b² − c²)) and its parameter; nlerp is the same in any
// component order, so the rebuilt one is put back in its place on store.
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
  void Add(const float* a, const float* b, float u, int dropped, Out* out) {
    for (int c = 0; c < 3; ++c) {
      a_[c][n_] = a[c];
      b_[c][n_] = b[c];
    }
    u_[n_] = u;
    dropped_[n_] = dropped;
    out_[n_] = out;
    if (++n_ == 4) Flush();
  }

  void Flush() {
    if (n_ == 0) return;
    for (size_t lane = n_; lane < 4; ++lane) {  // unused lanes: identity
      for (int c = 0; c < 3; ++c) a_[c][lane] = b_[c][lane] = 0.f;
      u_[lane] = 0.f;
    }
    const v4 zero = Splat(0.f), one = Splat(1.f);
    const v4 wa = Sqrt(Max(one - a_[0] * a_[0] - a_[1] * a_[1] - a_[2] * a_[2], zero));
    const v4 wb = Sqrt(Max(one - b_[0] * b_[0] - b_[1] * b_[1] - b_[2] * b_[2], zero));
    const v4 d = a_[0] * b_[0] + a_[1] * b_[1] + a_[2] * b_[2] + wa * wb;
    const v4 ub = Select(d < zero, -u_, u_), ua = one - u_;
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
    for (size_t lane = 0; lane < n_; ++lane) {
      if constexpr (std::is_same_v<Out, float>) {
        float* q = out_[lane];  // x y z w
        for (int c = 0, k = 0; c < 4; ++c) q[c] = c == dropped_[lane] ? r[3][lane] : r[k++][lane];
      } else {
        double q[4];  // x y z w
        for (int c = 0, k = 0; c < 4; ++c) q[c] = c == dropped_[lane] ? r[3][lane] : r[k++][lane];
        out_[lane]->rotation = Eigen::Quaterniond(q[3], q[0], q[1], q[2]);
        MakeUnit(out_[lane]->rotation);
      }
    }
    n_ = 0;
  }

 private:
  v4 a_[3], b_[3], u_;
  int dropped_[4];
  Out* out_[4];
  size_t n_ = 0;
};

using RotationBatch = RotationBatchOf<Trs>;

}  // namespace armature::compression_internal
