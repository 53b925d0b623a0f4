// What every crowd session of the server shares: the characters held in all
// (capped by --max-crowd-characters-total) and the counters /metrics shows
// (armature_crowd_*). Lock-free: sessions add to it on their own threads.
#pragma once

#include <atomic>
#include <cstdint>

#include "server/rpc/metrics.h"

namespace armature::server {

class CrowdTotals {
 public:
  explicit CrowdTotals(int64_t max_characters) : max_characters_(max_characters) {}

  // One more character, unless the server holds max_characters already.
  bool TryAddCharacter();
  void RemoveCharacters(int64_t count) { characters_.fetch_sub(count, std::memory_order_relaxed); }
  int64_t characters() const { return characters_.load(std::memory_order_relaxed); }
  int64_t max_characters() const { return max_characters_; }

  // One tick of a session: its late flag, characters deferred, bytes sent.
  void CountTick(bool late, uint64_t deferred, uint64_t bytes);

  // armature_crowd_characters (gauge), armature_crowd_ticks_total,
  // armature_crowd_late_ticks_total, armature_crowd_deferred_characters_total,
  // armature_crowd_bytes_sent_total.
  void Collect(PrometheusText& out) const;

 private:
  const int64_t max_characters_;
  std::atomic<int64_t> characters_{0};
  std::atomic<uint64_t> ticks_{0}, late_ticks_{0}, deferred_{0}, bytes_{0};
};

}  // namespace armature::server
