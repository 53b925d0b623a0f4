// The peak of heap bytes a piece of code allocates, for benchmark counters:
// the binary that links heap_peak.cc counts every global operator new and
// delete while a measurement runs (one relaxed load when none does).
#pragma once

#include <functional>

namespace armature_bench {

// The peak of heap bytes in use while `run` runs once, counted from 0 at
// its start (what it frees of earlier allocations counts below 0).
double PeakHeapBytesOf(const std::function<void()>& run);

}  // namespace armature_bench
