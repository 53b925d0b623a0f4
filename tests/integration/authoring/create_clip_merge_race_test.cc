// Concurrent CreateClip merges into one clip on a real server: each merge
// reads the stored clip and writes it back, so without the store's
// compare-and-swap (ImportRequest::replace_only) a merge landing between
// another's read and write was lost. Every merged track must survive.
#include <atomic>
#include <memory>
#include <string>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "authoring/create_clip_support.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

TEST(CreateClipMergeRace, EveryConcurrentMergeKeepsItsTrack) {
  TempDir data;
  ServerProcess server(data.path());
  client::Client client(OptionsFor(server));
  KeyMaker make;
  const v1::Skeleton skeleton = client.GetSkeleton("demo_walk");
  ASSERT_GT(skeleton.joints_size(), 13);

  v1::CreateClipRequest first;
  first.set_skeleton("demo_walk");
  first.set_name("race");
  const std::vector<double> times = make.Times(3);
  *first.add_tracks() = Keys("Hips", times, {make.Rotation(), make.Rotation(), make.Rotation()}, {}, v1::LINEAR);
  client.CreateClip(first);

  // Twelve joints, one merge each, all let go at once.
  constexpr int kMerges = 12;
  std::vector<std::string> joints;
  std::vector<Eigen::Quaterniond> keyed;
  for (int j = 1; j <= kMerges; ++j) {
    joints.push_back(skeleton.joints(j).name());
    keyed.push_back(make.Rotation());
  }
  std::atomic<int> ready{0};
  std::atomic<int> failed{0};
  std::vector<std::thread> threads;
  for (int i = 0; i < kMerges; ++i) {
    threads.emplace_back([&, i] {
      client::Client own(OptionsFor(server));
      v1::CreateClipRequest merge;
      merge.set_name("race");
      merge.set_merge(true);
      *merge.add_tracks() = Keys(joints[i], {times[0]}, {keyed[i]}, {}, v1::STEP);
      ++ready;
      while (ready.load() < kMerges) std::this_thread::yield();
      try {
        own.CreateClip(merge);
      } catch (const std::exception& e) {
        ADD_FAILURE() << joints[i] << ": " << e.what();
        ++failed;
      }
    });
  }
  for (std::thread& t : threads) t.join();
  ASSERT_EQ(failed.load(), 0);

  for (int i = 0; i < kMerges; ++i) {
    const Local at = SampleLocal(client, "race", joints[i], {times[0]})[0];
    EXPECT_LT(keyed[i].angularDistance(at.rotation), 1e-6) << joints[i] << "'s merged track was lost";
  }
}

}  // namespace
}  // namespace armature::testing
