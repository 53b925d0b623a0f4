#include "armature/engine/anim/crowd/crowd_schedule.h"

#include <algorithm>
#include <cmath>

namespace armature {

size_t AssignIntervals(std::span<const uint32_t> ranked, double capacity, uint32_t max_interval,
                       std::span<uint8_t> intervals) {
  const uint32_t top = std::clamp<uint32_t>(max_interval, 1, 255);
  double left = capacity;  // updates a tick still unspent
  size_t reduced = 0;
  size_t after = ranked.size();
  for (uint32_t slot : ranked) {
    --after;
    // The rest at the longest interval need after/top; this one may spend the remainder.
    const double spare = left - static_cast<double>(after) / top;
    uint32_t interval = top;
    if (spare >= 1 - 1e-9)
      interval = 1;
    else if (spare > 1e-9)
      interval = std::min<uint32_t>(top, static_cast<uint32_t>(std::ceil(1 / spare - 1e-9)));
    intervals[slot] = static_cast<uint8_t>(interval);
    left -= 1.0 / interval;
    if (interval > 1) ++reduced;
  }
  return reduced;
}

size_t SelectDue(std::span<const uint32_t> ranked, const ScheduleState& state, int64_t tick, size_t cap,
                 std::span<uint32_t> due) {
  size_t count = 0;
  for (uint32_t slot : ranked) {  // deferred before: taken whatever the cap
    const int64_t last = state.last_tick[slot];
    if (last >= 0 && tick - last > state.intervals[slot]) due[count++] = slot;
  }
  for (uint32_t slot : ranked) {
    if (count >= cap) break;
    const int64_t last = state.last_tick[slot];
    if (last < 0 || tick - last == state.intervals[slot]) due[count++] = slot;
  }
  for (size_t i = 0; i < count; ++i) state.last_tick[due[i]] = tick;
  return count;
}

}  // namespace armature
