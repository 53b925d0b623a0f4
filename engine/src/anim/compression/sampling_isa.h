// Internal: which build of the sampling job's core runs
// (clip_sampling_job.cc): its AVX2 clone on a CPU with AVX2 and BMI2,
// else the baseline. Both give the same values; tests switch between them
// to check that on one machine.
#pragma once

// Whether this build has the clone (GCC or Clang on x86-64).
#if defined(__x86_64__) && defined(__GNUC__)
#define ARMATURE_SAMPLING_AVX2 1
#else
#define ARMATURE_SAMPLING_AVX2 0
#endif

namespace armature::compression_internal {

// True when the CPU can run the AVX2 clone.
bool CpuRunsSamplingAvx2();

// Whether jobs use the clone (at start: CpuRunsSamplingAvx2()). Asking for
// it on a CPU that cannot run it keeps the baseline. For tests: switch it
// only while no job runs.
bool SamplingUsesAvx2();
void UseSamplingAvx2(bool on);

}  // namespace armature::compression_internal
