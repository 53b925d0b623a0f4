// Internal: forward kinematics over plain arrays, compiled once more with
// AVX2 on x86-64 (fk_kernels_avx2.cc) and picked at run time by fk.cc.
#pragma once

#include <cstddef>

namespace armature::fk_internal {

// Plain pointers only: the AVX2 translation unit includes no Eigen, whose
// alignment (and so Trs's layout) changes with -mavx, so nothing compiled
// for AVX2 can leak into the baseline build.
struct FkInput {
  size_t joints = 0;
  const int* parents = nullptr;  // parents[i] < i, -1 for a root
  // The local Trs array as bytes: element i at local + i * local_stride,
  // its translation (x y z), rotation (x y z w) and scale (x y z) doubles
  // at these byte offsets.
  const char* local = nullptr;
  size_t local_stride = 0, translation_offset = 0, rotation_offset = 0, scale_offset = 0;
  double* world = nullptr;  // 16 doubles (a column-major 4×4) per joint
};

namespace avx2 {
bool Available();  // compiled in and supported by this CPU
// world[i] = world[parent] · T·R·S, bit for bit as fk.cc's scalar loop.
void ComputeWorld(const FkInput& in);
// world_rotation[i] (x y z w, 4 doubles a joint) = world_rotation[parent] ·
// the local rotation, bit for bit as fk.cc's QuaternionProduct.
void ComputeWorldRotations(const FkInput& in, double* world_rotation);
}  // namespace avx2

}  // namespace armature::fk_internal
