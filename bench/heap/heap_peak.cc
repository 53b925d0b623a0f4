#include "heap_peak.h"

#include <malloc.h>

#include <atomic>
#include <cstdint>
#include <cstdlib>
#include <new>

namespace {

std::atomic<bool> tracking{false};
std::atomic<int64_t> live_bytes{0}, peak_bytes{0};

void Count(int64_t delta) {
  const int64_t now = live_bytes.fetch_add(delta, std::memory_order_relaxed) + delta;
  int64_t peak = peak_bytes.load(std::memory_order_relaxed);
  while (now > peak && !peak_bytes.compare_exchange_weak(peak, now, std::memory_order_relaxed)) {}
}

}  // namespace

namespace armature_bench {

double PeakHeapBytesOf(const std::function<void()>& run) {
  live_bytes = 0;
  peak_bytes = 0;
  tracking = true;
  run();
  tracking = false;
  return static_cast<double>(peak_bytes.load());
}

}  // namespace armature_bench

void* operator new(size_t size) {
  void* p = std::malloc(size ? size : 1);
  if (p == nullptr) throw std::bad_alloc();
  if (tracking.load(std::memory_order_relaxed)) Count(static_cast<int64_t>(malloc_usable_size(p)));
  return p;
}
void* operator new[](size_t size) { return operator new(size); }
void operator delete(void* p) noexcept {
  if (p != nullptr && tracking.load(std::memory_order_relaxed)) Count(-static_cast<int64_t>(malloc_usable_size(p)));
  std::free(p);
}
void operator delete[](void* p) noexcept { operator delete(p); }
void operator delete(void* p, size_t) noexcept { operator delete(p); }
void operator delete[](void* p, size_t) noexcept { operator delete(p); }
