// Forward kinematics with AVX2 (engine/CMakeLists.txt compiles this file with
// -mavx2 and without FMA on x86-64; fk.cc picks it at run time).
//
// Four joints at a time, their quaternions and scales are transposed into
// lanes and turned into rotation·scale matrices with Eigen's own formula
// (toRotationMatrix), one lane per joint. Then, joint by joint, each world
// column is the parent's four columns (one register each) weighted by the
// local matrix's entries, broadcast from memory. Every product and sum is
// the scalar loop's, in its order and without fused multiply-adds, so the
// matrices are bit for bit those of fk.cc's scalar loop.
#include "fk_kernels.h"

#if defined(ARMATURE_HAVE_AVX2_KERNELS)

#include <immintrin.h>

#include <algorithm>

namespace armature::fk_internal::avx2 {
namespace {

constexpr size_t kLanes = 4;

// Rows a, b, c, d of a 4×4 block → its columns, in place.
inline void Transpose(__m256d& a, __m256d& b, __m256d& c, __m256d& d) {
  const __m256d ab_lo = _mm256_unpacklo_pd(a, b), ab_hi = _mm256_unpackhi_pd(a, b);
  const __m256d cd_lo = _mm256_unpacklo_pd(c, d), cd_hi = _mm256_unpackhi_pd(c, d);
  a = _mm256_permute2f128_pd(ab_lo, cd_lo, 0x20);
  b = _mm256_permute2f128_pd(ab_hi, cd_hi, 0x20);
  c = _mm256_permute2f128_pd(ab_lo, cd_lo, 0x31);
  d = _mm256_permute2f128_pd(ab_hi, cd_hi, 0x31);
}

// The local rotation·scale matrices of joints [first, first + 4) (the last
// joint repeated past the end), entry (row k, column j) of lane l at
// linear[(3 * j + k) * 4 + l].
void LocalLinear(const FkInput& in, size_t first, double* linear) {
  const char* joint[kLanes];
  for (size_t l = 0; l < kLanes; ++l) joint[l] = in.local + std::min(first + l, in.joints - 1) * in.local_stride;
  __m256d x = _mm256_loadu_pd(reinterpret_cast<const double*>(joint[0] + in.rotation_offset));
  __m256d y = _mm256_loadu_pd(reinterpret_cast<const double*>(joint[1] + in.rotation_offset));
  __m256d z = _mm256_loadu_pd(reinterpret_cast<const double*>(joint[2] + in.rotation_offset));
  __m256d w = _mm256_loadu_pd(reinterpret_cast<const double*>(joint[3] + in.rotation_offset));
  Transpose(x, y, z, w);
  const __m256i xyz = _mm256_set_epi64x(0, -1, -1, -1);  // the scale's three doubles, nothing past them
  __m256d sx = _mm256_maskload_pd(reinterpret_cast<const double*>(joint[0] + in.scale_offset), xyz);
  __m256d sy = _mm256_maskload_pd(reinterpret_cast<const double*>(joint[1] + in.scale_offset), xyz);
  __m256d sz = _mm256_maskload_pd(reinterpret_cast<const double*>(joint[2] + in.scale_offset), xyz);
  __m256d unused = _mm256_maskload_pd(reinterpret_cast<const double*>(joint[3] + in.scale_offset), xyz);
  Transpose(sx, sy, sz, unused);

  const __m256d two = _mm256_set1_pd(2), one = _mm256_set1_pd(1);
  const __m256d tx = _mm256_mul_pd(two, x), ty = _mm256_mul_pd(two, y), tz = _mm256_mul_pd(two, z);
  const __m256d twx = _mm256_mul_pd(tx, w), twy = _mm256_mul_pd(ty, w), twz = _mm256_mul_pd(tz, w);
  const __m256d txx = _mm256_mul_pd(tx, x), txy = _mm256_mul_pd(ty, x), txz = _mm256_mul_pd(tz, x);
  const __m256d tyy = _mm256_mul_pd(ty, y), tyz = _mm256_mul_pd(tz, y), tzz = _mm256_mul_pd(tz, z);
  const __m256d entries[9] = {
      // column 0 (× sx), column 1 (× sy), column 2 (× sz); rows 0, 1, 2 in each
      _mm256_mul_pd(_mm256_sub_pd(one, _mm256_add_pd(tyy, tzz)), sx),
      _mm256_mul_pd(_mm256_add_pd(txy, twz), sx),
      _mm256_mul_pd(_mm256_sub_pd(txz, twy), sx),
      _mm256_mul_pd(_mm256_sub_pd(txy, twz), sy),
      _mm256_mul_pd(_mm256_sub_pd(one, _mm256_add_pd(txx, tzz)), sy),
      _mm256_mul_pd(_mm256_add_pd(tyz, twx), sy),
      _mm256_mul_pd(_mm256_add_pd(txz, twy), sz),
      _mm256_mul_pd(_mm256_sub_pd(tyz, twx), sz),
      _mm256_mul_pd(_mm256_sub_pd(one, _mm256_add_pd(txx, tyy)), sz),
  };
  for (size_t e = 0; e < 9; ++e) _mm256_store_pd(linear + kLanes * e, entries[e]);
}

// A 4×4 matrix, a column per register.
struct Columns {
  __m256d c0, c1, c2, c3;
};

inline Columns Load(const double* m) {
  return {_mm256_loadu_pd(m), _mm256_loadu_pd(m + 4), _mm256_loadu_pd(m + 8), _mm256_loadu_pd(m + 12)};
}

// Row 3 is stored as exactly 0 0 0 1, as the scalar loop writes it (the
// products give -0 for negative entries, NaN for infinite ones).
inline void Store(double* out, const Columns& m) {
  const __m256d zero = _mm256_setzero_pd();
  _mm256_storeu_pd(out, _mm256_blend_pd(m.c0, zero, 0b1000));
  _mm256_storeu_pd(out + 4, _mm256_blend_pd(m.c1, zero, 0b1000));
  _mm256_storeu_pd(out + 8, _mm256_blend_pd(m.c2, zero, 0b1000));
  _mm256_storeu_pd(out + 12, _mm256_blend_pd(m.c3, _mm256_set1_pd(1), 0b1000));
}

// Column j of the product: parent columns p0, p1, p2 weighted by the local
// entries (0, j), (1, j), (2, j), summed in the scalar loop's order.
inline __m256d Column(const Columns& p, const double* entry0, const double* entry1, const double* entry2) {
  const __m256d sum =
      _mm256_add_pd(_mm256_mul_pd(p.c0, _mm256_broadcast_sd(entry0)), _mm256_mul_pd(p.c1, _mm256_broadcast_sd(entry1)));
  return _mm256_add_pd(sum, _mm256_mul_pd(p.c2, _mm256_broadcast_sd(entry2)));
}

// A joint's world matrix (row 3 not yet exact) from its parent's, its local
// rotation·scale entries e[(3 * j + k) * 4] and its translation t.
inline Columns Child(const Columns& parent, const double* e, const double* t) {
  return {Column(parent, e, e + 4, e + 8), Column(parent, e + 12, e + 16, e + 20),
          Column(parent, e + 24, e + 28, e + 32), _mm256_add_pd(Column(parent, t, t + 1, t + 2), parent.c3)};
}

// A root: its local matrix is its world matrix.
inline void RootWorld(const double* e, const double* t, double* out) {
  for (size_t j = 0; j < 3; ++j) {
    for (size_t k = 0; k < 3; ++k) out[4 * j + k] = e[(3 * j + k) * kLanes];
    out[4 * j + 3] = 0;
  }
  out[12] = t[0], out[13] = t[1], out[14] = t[2], out[15] = 1;
}

// a·b for the quaternion a in a register (x y z w) and b's components
// broadcast from memory: ((bw·a + bx·a1) + by·a2) + bz·a3, a1..a3 signed
// permutations of a, as fk.cc's QuaternionProduct sums them.
inline __m256d Product(__m256d a, const double* b) {
  const __m256d a1 = _mm256_xor_pd(_mm256_permute4x64_pd(a, _MM_SHUFFLE(0, 1, 2, 3)),  // aw az -ay -ax
                                   _mm256_set_pd(-0.0, -0.0, 0.0, 0.0));
  const __m256d a2 = _mm256_xor_pd(_mm256_permute4x64_pd(a, _MM_SHUFFLE(1, 0, 3, 2)),  // -az aw ax -ay
                                   _mm256_set_pd(-0.0, 0.0, 0.0, -0.0));
  const __m256d a3 = _mm256_xor_pd(_mm256_permute4x64_pd(a, _MM_SHUFFLE(2, 3, 0, 1)),  // ay -ax aw -az
                                   _mm256_set_pd(-0.0, 0.0, -0.0, 0.0));
  __m256d q = _mm256_add_pd(_mm256_mul_pd(_mm256_broadcast_sd(b + 3), a), _mm256_mul_pd(_mm256_broadcast_sd(b), a1));
  q = _mm256_add_pd(q, _mm256_mul_pd(_mm256_broadcast_sd(b + 1), a2));
  return _mm256_add_pd(q, _mm256_mul_pd(_mm256_broadcast_sd(b + 2), a3));
}

}  // namespace

bool Available() { return __builtin_cpu_supports("avx2"); }

void ComputeWorld(const FkInput& in) {
  alignas(32) double linear[9 * kLanes];
  // The joint before, kept in registers: along a chain (a parent just before
  // its child, most joints) the child reads it without waiting on the store.
  Columns previous{};
  for (size_t first = 0; first < in.joints; first += kLanes) {
    LocalLinear(in, first, linear);
    const size_t end = std::min(first + kLanes, in.joints);
    for (size_t i = first; i < end; ++i) {
      const double* t = reinterpret_cast<const double*>(in.local + i * in.local_stride + in.translation_offset);
      double* out = in.world + 16 * i;
      const int parent = in.parents[i];
      if (parent < 0) {
        RootWorld(linear + (i - first), t, out);
        previous = Load(out);
        continue;
      }
      const Columns p =
          static_cast<size_t>(parent) + 1 == i ? previous : Load(in.world + 16 * static_cast<size_t>(parent));
      previous = Child(p, linear + (i - first), t);
      Store(out, previous);
    }
  }
}

void ComputeWorldRotations(const FkInput& in, double* world_rotation) {
  __m256d previous = _mm256_setzero_pd();  // the joint before, as in ComputeWorld
  for (size_t i = 0; i < in.joints; ++i) {
    const double* local = reinterpret_cast<const double*>(in.local + i * in.local_stride + in.rotation_offset);
    const int parent = in.parents[i];
    if (parent < 0)
      previous = _mm256_loadu_pd(local);
    else
      previous = Product(static_cast<size_t>(parent) + 1 == i
                             ? previous
                             : _mm256_loadu_pd(world_rotation + 4 * static_cast<size_t>(parent)),
                         local);
    _mm256_storeu_pd(world_rotation + 4 * i, previous);
  }
}

}  // namespace armature::fk_internal::avx2

#else  // no AVX2 build on this target: fk.cc's scalar loop runs

namespace armature::fk_internal::avx2 {
bool Available() { return false; }
void ComputeWorld(const FkInput&) {}
void ComputeWorldRotations(const FkInput&, double*) {}
}  // namespace armature::fk_internal::avx2

#endif
