// The crowd's budgeted schedule (issue 31): intervals by significance that
// fit the capacity, updates a tick bounded by it in the steady state, and no
// character waiting more than its interval + 1.
#include <algorithm>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/crowd/crowd_schedule.h"

namespace armature {
namespace {

std::vector<uint32_t> Ranked(size_t n) {
  std::vector<uint32_t> ranked(n);
  std::iota(ranked.begin(), ranked.end(), 0u);
  return ranked;
}

double Rate(const std::vector<uint8_t>& intervals) {
  double rate = 0;
  for (uint8_t d : intervals) rate += 1.0 / d;
  return rate;
}

TEST(CrowdScheduleTest, EnoughCapacityTicksEveryCharacterEveryTick) {
  std::vector<uint8_t> intervals(100, 0);
  EXPECT_EQ(AssignIntervals(Ranked(100), 100, 8, intervals), 0u);
  EXPECT_TRUE(std::all_of(intervals.begin(), intervals.end(), [](uint8_t d) { return d == 1; }));
}

TEST(CrowdScheduleTest, AShortBudgetSpreadsTheLeastSignificant) {
  std::vector<uint8_t> intervals(1000, 0);
  const size_t reduced = AssignIntervals(Ranked(1000), 400, 8, intervals);
  EXPECT_LE(Rate(intervals), 400 + 1e-6);
  EXPECT_GE(Rate(intervals), 399);  // the budget is spent, not wasted
  EXPECT_EQ(intervals.front(), 1);
  EXPECT_EQ(intervals.back(), 8);
  EXPECT_TRUE(std::is_sorted(intervals.begin(), intervals.end()));  // less significant, never more often
  // (1000 − k)/8 + k = 400 for the k at 1: 314 characters every tick, the rest at 8 (one in between).
  EXPECT_NEAR(static_cast<double>(std::count(intervals.begin(), intervals.end(), 1)), 314, 1);
  EXPECT_EQ(reduced, 1000 - static_cast<size_t>(std::count(intervals.begin(), intervals.end(), 1)));
}

TEST(CrowdScheduleTest, ABudgetTooShortEvenAtTheLongestIntervalGivesItToAll) {
  std::vector<uint8_t> intervals(1000, 0);
  EXPECT_EQ(AssignIntervals(Ranked(1000), 50, 8, intervals), 1000u);
  EXPECT_TRUE(std::all_of(intervals.begin(), intervals.end(), [](uint8_t d) { return d == 8; }));
}

TEST(CrowdScheduleTest, SteadyTicksStayWithinTheCapacityAndNobodyStarves) {
  const size_t n = 10000;
  const double capacity = 3000;  // 10,000 characters, budget for 3,000 updates
  std::vector<uint8_t> intervals(n);
  AssignIntervals(Ranked(n), capacity, 8, intervals);
  std::vector<int64_t> last(n, -1);
  std::vector<uint32_t> due(n);
  const std::vector<uint32_t> ranked = Ranked(n);
  size_t most = 0, total = 0;
  int64_t worst_wait = 0;
  std::vector<int64_t> previous(n, -1);
  for (int64_t tick = 0; tick < 200; ++tick) {
    const size_t count = SelectDue(ranked, {intervals, last}, tick, 3000, due);
    if (tick >= 20) most = std::max(most, count), total += count;
    for (size_t i = 0; i < count; ++i) {
      const uint32_t slot = due[i];
      if (previous[slot] >= 0 && tick >= 20) worst_wait = std::max(worst_wait, tick - previous[slot] - intervals[slot]);
      previous[slot] = tick;
    }
  }
  EXPECT_LE(most, 3000u);
  EXPECT_NEAR(static_cast<double>(total) / 180, Rate(intervals), 30);  // the mean rate is the planned one
  EXPECT_LE(worst_wait, 1);
  for (size_t slot = 0; slot < n; ++slot) EXPECT_GE(previous[slot], 199 - 9) << slot;  // each updated lately
}

TEST(CrowdScheduleTest, ACrowdAddedAtOnceStartsOverSeveralTicks) {
  const size_t n = 1000;
  std::vector<uint8_t> intervals(n);
  AssignIntervals(Ranked(n), 300, 8, intervals);
  std::vector<int64_t> last(n, -1);
  std::vector<uint32_t> due(n);
  EXPECT_EQ(SelectDue(Ranked(n), {intervals, last}, 0, 300, due), 300u);
  EXPECT_EQ(due[0], 0u);  // the most significant first
  EXPECT_EQ(SelectDue(Ranked(n), {intervals, last}, 1, 300, due), 300u);
}

}  // namespace
}  // namespace armature
