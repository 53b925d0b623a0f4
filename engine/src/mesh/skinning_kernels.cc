#include "skinning_kernels.h"

#if defined(__SSE__)
#include <immintrin.h>
#endif

// The vector types never cross a non-inlined call boundary.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace armature::skinning_internal {

namespace generic {
#include "skinning_kernels.inc"
}  // namespace generic

#if !defined(ARMATURE_HAVE_AVX2_KERNELS)
namespace avx2 {
bool Available() { return false; }
void SkinRange(const KernelInput& in, uint32_t begin, uint32_t end) { generic::SkinRange(in, begin, end); }
}  // namespace avx2
#endif

void SkinRange(const KernelInput& in, uint32_t begin, uint32_t end) {
  static const bool use_avx2 = avx2::Available();
  if (use_avx2)
    avx2::SkinRange(in, begin, end);
  else
    generic::SkinRange(in, begin, end);
}

}  // namespace armature::skinning_internal
