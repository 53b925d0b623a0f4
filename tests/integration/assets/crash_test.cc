// kill -9 during imports, replaces and deletes: after a restart every
// acknowledged change is there exactly as acknowledged, the one change in
// flight is either wholly there or wholly absent, nothing half-written
// shows, and the start leaves no leftover file in the data dir.
#include <csignal>
#include <map>
#include <mutex>
#include <optional>
#include <random>
#include <string>
#include <thread>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/data_dir_check.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

constexpr int kTrials = 16;
constexpr int kNames = 4;

// What the stored state of one name is: a clip of `frames` frames, or none (0).
using State = std::map<std::string, int>;

struct Change {
  std::string name;
  int frames = 0;  // 0: a delete
};

// Changes the store until the server dies, recording what it acknowledged.
class Writer {
 public:
  Writer(const ServerProcess& server, State& acked, unsigned seed)
      : client_(OptionsFor(server)), acked_(acked), rng_(seed) {}

  void Run() {
    for (int op = 0; op < 100000; ++op) {
      Change change;
      change.name = "a" + std::to_string(rng_() % kNames);
      const bool exists = acked_[change.name] > 0;
      change.frames = exists && rng_() % 4 == 0 ? 0 : 1500 + static_cast<int>(rng_() % 3000);  // 50–150 KB
      {
        std::lock_guard lock(mu_);
        in_flight_ = change;
      }
      const grpc::Status st = StatusOf([&] {
        if (change.frames == 0)
          client_.DeleteAsset(change.name);
        else
          client_.Import({change.name + ".bvh", ArmBvhWithFrames(change.frames)}, "", "", exists);
      });
      if (!st.ok()) return;  // the server is gone; the change stays in flight
      std::lock_guard lock(mu_);
      acked_[change.name] = change.frames;
      in_flight_.reset();
    }
  }
  std::optional<Change> in_flight() {
    std::lock_guard lock(mu_);
    return in_flight_;
  }

 private:
  client::Client client_;
  State& acked_;
  std::mt19937 rng_;
  std::mutex mu_;
  std::optional<Change> in_flight_;
};

// The frames of `name`'s clip as the restarted server serves it, 0 if absent.
int ServedFrames(client::Client& client, const std::string& name) {
  int frames = 0;
  const grpc::Status st = StatusOf([&] { frames = client.GetClip(name).frames(); });
  if (st.error_code() == grpc::StatusCode::NOT_FOUND) return 0;
  EXPECT_TRUE(st.ok()) << name << ": " << st.error_message();
  return frames;
}

TEST(Crash, KillNineDuringWritesKeepsEveryAcknowledgedChange) {
  TempDir data;
  State acked;
  std::mt19937 rng(20261125);
  for (int trial = 0; trial < kTrials; ++trial) {
    SCOPED_TRACE("trial " + std::to_string(trial));
    std::optional<Change> in_flight;
    {
      ServerProcess server(data.path(), {"--no-demo"});
      Writer writer(server, acked, rng());
      std::thread t([&] { writer.Run(); });
      std::this_thread::sleep_for(std::chrono::milliseconds(100 + rng() % 700));  // the moment of the crash
      ::kill(server.pid(), SIGKILL);
      t.join();
      in_flight = writer.in_flight();
      server.Stop(SIGKILL);  // reaps it
    }
    ServerProcess server(data.path(), {"--no-demo"});
    client::Client client(OptionsFor(server));
    EXPECT_EQ(LeftoverFiles(data.path()), std::vector<std::string>{}) << "the start left leftovers";
    const std::string log = ReadFile(server.log_file());
    EXPECT_EQ(log.find("could not be loaded"), std::string::npos) << log;
    EXPECT_EQ(log.find("skipping an entry"), std::string::npos) << log;
    std::set<std::string> expected_names;
    for (int i = 0; i < kNames; ++i) {
      const std::string name = "a" + std::to_string(i);
      const int served = ServedFrames(client, name);
      if (in_flight && in_flight->name == name) {
        // Unacknowledged: the old state or the new one, never anything else.
        EXPECT_TRUE(served == acked[name] || served == in_flight->frames)
            << name << ": serves " << served << " frames; acknowledged " << acked[name] << ", in flight "
            << in_flight->frames;
        acked[name] = served;  // what the next trial starts from
      } else {
        EXPECT_EQ(served, acked[name]) << name;
      }
      if (served > 0) expected_names.insert(name);
    }
    EXPECT_EQ(AssetNames(client), expected_names);
    EXPECT_EQ(ManifestAssetNames(data.path()), expected_names);
  }
}

}  // namespace
}  // namespace armature::testing
