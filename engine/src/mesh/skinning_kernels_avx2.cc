// The skinning kernels built for AVX2+FMA (engine/CMakeLists.txt compiles
// this file with -mavx2 -mfma on x86-64 and defines
// ARMATURE_HAVE_AVX2_KERNELS for the engine); chosen at run time when the
// CPU supports them.
#include "skinning_kernels.h"

#if defined(__SSE__)
#include <immintrin.h>
#endif

#if defined(ARMATURE_HAVE_AVX2_KERNELS)

namespace armature::skinning_internal::avx2 {

#include "skinning_kernels.inc"

bool Available() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }

}  // namespace armature::skinning_internal::avx2

#endif
