// Internal: the per-vertex skinning loops over a runtime vertex range. The
// loops are compiled once for the baseline ISA and, on x86-64, once more
// with AVX2+FMA, picked at run time (skinning_kernels.inc).
#pragma once

#include <cstddef>
#include <cstdint>

#include "armature/engine/mesh/mesh.h"
#include "armature/engine/mesh/skinning.h"

namespace armature::skinning_internal {

// Plain pointers only: the kernel translation units use no library code, so
// nothing compiled for AVX2 can leak into the baseline build.
struct KernelInput {
  const SkinningLayout::Group* groups = nullptr;
  size_t group_count = 0;
  const uint32_t* order = nullptr;         // runtime index → mesh vertex
  const uint16_t* joints = nullptr;        // skin joint per influence
  const uint32_t* pair_offsets = nullptr;  // DQS: per influence, 8 × its (heaviest joint, joint) pair
  const float* weights = nullptr;
  // Source geometry in runtime order (the rest layout or the morphed copy).
  const float *x = nullptr, *y = nullptr, *z = nullptr;
  const float *nx = nullptr, *ny = nullptr, *nz = nullptr;  // null: no normals
  bool unit_normals = false;  // the source normals are unit length (rest normals, no normal morph)
  SkinningMethod method = SkinningMethod::kLinear;
  bool skin = true;                         // false: copy the (morphed) rest geometry
  const float* matrices = nullptr;          // 16 floats (4 columns) per skin joint
  const float* normal_matrices = nullptr;   // same layout; null: normals use `matrices`
  const float* dual_quaternions = nullptr;  // 8 floats (real x y z w, dual x y z w) per pair slot, sign-aligned
  const float* stretch = nullptr;           // 16 floats per joint; null: every joint is rigid
  float* positions = nullptr;               // mesh vertex order, 3 per vertex
  float* normals = nullptr;                 // null: skip normals
};

// Skins runtime vertices [begin, end) with the fastest kernels the CPU runs.
void SkinRange(const KernelInput& in, uint32_t begin, uint32_t end);

// The two builds of the kernels (SkinRange picks one).
namespace generic {
void SkinRange(const KernelInput& in, uint32_t begin, uint32_t end);
}
namespace avx2 {
bool Available();  // compiled in and supported by this CPU
void SkinRange(const KernelInput& in, uint32_t begin, uint32_t end);
}  // namespace avx2

}  // namespace armature::skinning_internal
