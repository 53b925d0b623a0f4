// Reads racing writes: list calls while other clients import and delete.
#include <atomic>
#include <chrono>
#include <thread>
#include <vector>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

// ListAssets/ListClips/ListSkeletons used to iterate a catalog snapshot that
// no one held, so a concurrent import or delete freed it under the loop.
TEST(Concurrency, ListsRacingImportsAndDeletesAllAnswerOk) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  constexpr int kWriters = 2, kReaders = 4, kCycles = 60;
  std::atomic<int> writers_left{kWriters};
  std::atomic<int> failures{0};
  std::atomic<long> lists{0};
  std::vector<std::thread> threads;
  for (int w = 0; w < kWriters; ++w)
    threads.emplace_back([&, w] {
      client::Client client(OptionsFor(server));
      for (int i = 0; i < kCycles; ++i) {
        const std::string name = "arm" + std::to_string(w) + "_" + std::to_string(i % 3);
        if (!StatusOf([&] { client.Import({"arm.bvh", kArmBvh}, name); }).ok()) ++failures;
        if (!StatusOf([&] { client.DeleteAsset(name); }).ok()) ++failures;
      }
      --writers_left;
    });
  for (int r = 0; r < kReaders; ++r)
    threads.emplace_back([&] {
      client::Client client(OptionsFor(server));
      while (writers_left > 0) {
        const grpc::Status st = StatusOf([&] {
          client.ListAssets();
          client.ListClips();
          client.ListSkeletons();
        });
        if (!st.ok()) {
          ++failures;
          ADD_FAILURE() << st.error_code() << " " << st.error_message();
          return;
        }
        ++lists;
      }
    });
  for (auto& t : threads) t.join();
  EXPECT_EQ(failures, 0);
  EXPECT_GT(lists, 0);
  // The server survived and still answers.
  client::Client client(OptionsFor(server));
  EXPECT_TRUE(client.ListAssets().assets().empty());
  EXPECT_EQ(server.Stop(SIGTERM), 0);
}

}  // namespace
}  // namespace armature::testing
