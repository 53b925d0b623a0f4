// Which characters of a crowd a tick updates, under a budget (issue 31),
// after Unreal's Animation Budget Allocator: the budget buys `capacity`
// updates a tick (budget / measured cost of one update); characters ranked by
// significance get update intervals of 1 to max_interval ticks, the most
// significant every tick, so that Σ 1/interval ≤ capacity when it can be.
// Pure and allocation-free: the caller owns every span.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace armature {

// `ranked`: character slots, most significant first. Writes each slot's
// interval: greedily the smallest that still leaves the characters after it
// room at max_interval. When even max_interval for all exceeds the capacity,
// every one gets max_interval (the tick will be over budget). Returns how many
// got an interval over 1.
size_t AssignIntervals(std::span<const uint32_t> ranked, double capacity, uint32_t max_interval,
                       std::span<uint8_t> intervals);

// The per-character state the selection reads and updates.
struct ScheduleState {
  std::span<const uint8_t> intervals;  // by slot
  std::span<int64_t> last_tick;        // by slot: the tick of its last update; < 0 never updated
};

// Appends to `due` (room for every slot) the slots tick `tick` updates and
// returns their count: first every slot left over from an earlier tick
// (waited more than its interval), then, in rank order, those whose interval
// is up or never updated, while fewer than `cap` are taken. So no character
// waits more than its interval + 1 once updated, and a crowd added at once
// starts over several ticks. Marks the taken ones updated at `tick`.
size_t SelectDue(std::span<const uint32_t> ranked, const ScheduleState& state, int64_t tick, size_t cap,
                 std::span<uint32_t> due);

}  // namespace armature
