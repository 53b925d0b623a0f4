// FrameScheduler: tasks run in due order, not before they are due, and at
// scale one wake-up runs every task then due (what lets 1,000 streams at
// 60 fps share one thread, bench/load).
#include <gtest/gtest.h>

#include <atomic>
#include <mutex>
#include <thread>
#include <vector>

#include "server/rpc/streams/frame_scheduler.h"

namespace armature::server {
namespace {

using Clock = FrameScheduler::Clock;
using std::chrono::milliseconds;

TEST(FrameScheduler, RunsTasksInDueOrderAndNotBeforeTheirTime) {
  FrameScheduler scheduler;
  std::mutex mu;
  std::vector<int> order;
  std::vector<Clock::duration> early;  // due − run time, when positive
  std::atomic<int> done{0};
  const auto start = Clock::now();
  // Scheduled out of order: 30, 10, 20 ms.
  for (int k : {3, 1, 2}) {
    const auto due = start + milliseconds(10 * k);
    scheduler.Schedule(due, [&, k, due] {
      const auto now = Clock::now();
      std::lock_guard lock(mu);
      order.push_back(k);
      if (now < due) early.push_back(due - now);
      ++done;
    });
  }
  while (done < 3) std::this_thread::sleep_for(milliseconds(1));
  EXPECT_EQ(order, (std::vector<int>{1, 2, 3}));
  EXPECT_TRUE(early.empty()) << "a task ran before its due time";
}

TEST(FrameScheduler, OneWakeUpRunsEveryTaskThenDue) {
  FrameScheduler scheduler;
  constexpr int kTasks = 1000;
  std::atomic<int> done{0};
  // A thousand tasks all due at the same moment, 200 ms ahead: the thread
  // must not wake for each (it did, once per Schedule, before batching).
  const auto due = Clock::now() + milliseconds(200);
  for (int i = 0; i < kTasks; ++i) scheduler.Schedule(due, [&] { ++done; });
  while (done < kTasks) std::this_thread::sleep_for(milliseconds(1));
  const FrameScheduler::Counts counts = scheduler.counts();
  EXPECT_EQ(counts.tasks, static_cast<uint64_t>(kTasks));
  EXPECT_LE(counts.wakeups, 3u) << "tasks due together should run in one batch";
}

TEST(FrameScheduler, StopRunsWhatIsPendingAndLaterTasksInline) {
  std::atomic<int> ran{0};
  {
    FrameScheduler scheduler;
    scheduler.Schedule(Clock::now() + std::chrono::hours(1), [&] { ++ran; });
    scheduler.Stop();
    EXPECT_EQ(ran, 1) << "a pending task runs at Stop, however far its due time";
    scheduler.Schedule(Clock::now() + std::chrono::hours(1), [&] { ++ran; });
    EXPECT_EQ(ran, 2) << "after Stop a task runs inline";
  }
}

}  // namespace
}  // namespace armature::server
