#include "server/crowd/crowd_totals.h"

namespace armature::server {

bool CrowdTotals::TryAddCharacter() {
  int64_t held = characters_.load(std::memory_order_relaxed);
  while (held < max_characters_)
    if (characters_.compare_exchange_weak(held, held + 1, std::memory_order_relaxed)) return true;
  return false;
}

void CrowdTotals::CountTick(bool late, uint64_t deferred, uint64_t bytes) {
  ticks_.fetch_add(1, std::memory_order_relaxed);
  if (late) late_ticks_.fetch_add(1, std::memory_order_relaxed);
  deferred_.fetch_add(deferred, std::memory_order_relaxed);
  bytes_.fetch_add(bytes, std::memory_order_relaxed);
}

void CrowdTotals::Collect(PrometheusText& out) const {
  const auto load = [](const std::atomic<uint64_t>& v) {
    return static_cast<double>(v.load(std::memory_order_relaxed));
  };
  out.Family("armature_crowd_characters", "gauge", "Characters in every crowd session now.");
  out.Sample("armature_crowd_characters", {}, static_cast<double>(characters()));
  out.Family("armature_crowd_ticks_total", "counter", "Crowd ticks sent, every session together.");
  out.Sample("armature_crowd_ticks_total", {}, load(ticks_));
  out.Family("armature_crowd_late_ticks_total", "counter", "Crowd ticks filled over half a tick after they were due.");
  out.Sample("armature_crowd_late_ticks_total", {}, load(late_ticks_));
  out.Family("armature_crowd_deferred_characters_total", "counter",
             "Characters a crowd tick did not update (their turn not come under the budget), summed over ticks.");
  out.Sample("armature_crowd_deferred_characters_total", {}, load(deferred_));
  out.Family("armature_crowd_bytes_sent_total", "counter", "Bytes of crowd frames written, every session together.");
  out.Sample("armature_crowd_bytes_sent_total", {}, load(bytes_));
}

}  // namespace armature::server
