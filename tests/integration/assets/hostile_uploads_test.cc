// 1,000 hostile uploads in a row (random bytes, truncated and bit-flipped
// real files, size bombs), half over gRPC and half over REST: each is
// answered within 2 s with a client error (or, for a mutation that still
// parses, imported and deleted again), the server stays under 1 GB resident
// and keeps serving, what was stored is unchanged, and SIGTERM ends it
// cleanly; repeated by the thousand on one process, its resident memory
// levels off. Failures are gathered by kind and shape, so one run names every
// input the server mishandles.
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <httplib.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/hostile_uploads.h"
#include "support/process_memory.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

constexpr int kUploads = 1000;
constexpr uint32_t kSeed = 0xA11CE;
constexpr double kAnswerSeconds = 2.0;
constexpr int64_t kMaxResidentKb = 1 << 20;  // 1 GiB

// What the store serves, in a form that changes if anything stored does.
std::string StoredState(client::Client& client) {
  std::string state = client.ListAssets().SerializeAsString();
  const v1::ListClipsResponse clips = client.ListClips();  // named: a range-for over a temporary's member dangles
  for (const auto& clip : clips.clips()) {
    v1::EvaluateClipRequest r;
    r.set_clip(clip.name());
    for (double t : {0.0, 0.37, 1.0}) r.add_times(t);
    state += client.EvaluateClip(r).SerializeAsString();
  }
  return state;
}

struct Outcome {
  bool ok = false;          // imported (a mutation that still parses)
  bool acceptable = false;  // a client error, or OK
  std::string what;         // the status or HTTP answer, for the report
};

Outcome ViaGrpc(client::Client& client, const HostileUpload& u, const std::string& name) {
  const grpc::Status st = StatusOf([&] { client.Import({u.filename, u.bytes}, name); });
  const auto c = st.error_code();
  const bool client_error = c == grpc::StatusCode::INVALID_ARGUMENT || c == grpc::StatusCode::RESOURCE_EXHAUSTED ||
                            c == grpc::StatusCode::FAILED_PRECONDITION || c == grpc::StatusCode::ALREADY_EXISTS;
  return {st.ok(), st.ok() || (client_error && !st.error_message().empty()),
          std::string(client::StatusCodeName(c)) + ": " + st.error_message().substr(0, 200)};
}

Outcome ViaRest(httplib::Client& http, const HostileUpload& u, const std::string& name) {
  const auto r =
      http.Post("/v1/assets:import?filename=" + u.filename + "&name=" + name, u.bytes, "application/octet-stream");
  if (!r) return {false, false, "no HTTP answer (" + httplib::to_string(r.error()) + ")"};
  const bool client_error =
      r->status == 400 || r->status == 409 || r->status == 413 || r->status == 422 || r->status == 429;
  return {r->status == 200, r->status == 200 || client_error,
          "HTTP " + std::to_string(r->status) + ": " + r->body.substr(0, 200)};
}

// What a run of uploads found: failures by "<kind> via <transport>: <problem>".
struct RunReport {
  std::map<std::string, int> failures;
  std::map<std::string, std::string> first_example;
  std::map<std::string, int> imported;  // kind → mutations that still parsed
  double slowest = 0;
  int done = 0;

  std::string Failures() const {
    std::ostringstream report;
    for (const auto& [key, n] : failures)
      report << "\n  " << n << "× " << key << "\n      first: " << first_example.at(key);
    return report.str();
  }
};

// Sends `uploads` (alternately gRPC and REST, named from `first`), checking
// each answer, until done or `give_up`.
void RunUploads(const ServerProcess& server, client::Client& client, httplib::Client& http,
                const std::vector<HostileUpload>& uploads, int first, std::chrono::steady_clock::time_point give_up,
                RunReport& run) {
  for (int i = 0; i < static_cast<int>(uploads.size()); ++i, ++run.done) {
    if (std::chrono::steady_clock::now() > give_up) {
      ADD_FAILURE() << "gave up after " << run.done << " uploads";
      break;
    }
    const HostileUpload& u = uploads[i];
    const bool rest = i % 2 == 1;
    const std::string name = "hostile" + std::to_string(first + i);
    const auto t0 = std::chrono::steady_clock::now();
    const Outcome outcome = rest ? ViaRest(http, u, name) : ViaGrpc(client, u, name);
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    run.slowest = std::max(run.slowest, seconds);
    auto fail = [&](const std::string& problem) {
      const std::string key = u.kind + " via " + (rest ? "REST" : "gRPC") + ": " + problem;
      if (run.failures[key]++ == 0) {
        run.first_example[key] = "#" + std::to_string(first + i) + " " + u.filename + " (" +
                                 std::to_string(u.bytes.size()) + " B) → " + outcome.what;
        std::printf("  new failure: %s: %s\n", key.c_str(), run.first_example[key].c_str());  // seen even if cut short
        std::fflush(stdout);
      }
    };
    if (seconds > kAnswerSeconds) fail("answered after more than 2 s");
    if (!outcome.acceptable) fail("not a client error");
    if (outcome.ok) {
      ++run.imported[u.kind];
      if (CodeOf([&] { client.DeleteAsset(name); }) != grpc::StatusCode::OK) fail("imported but not deletable");
    }
    if (StatusKb(server.pid(), "VmRSS") > kMaxResidentKb) fail("server over 1 GB resident");
    if (StatusKb(server.pid(), "VmRSS") < 0) {
      fail("server died");
      break;
    }
  }
}

// The server for a run: should a bomb go off, it must not take the machine
// with it, so it inherits a 4 GB address-space cap, well above the 1 GB asserted.
std::unique_ptr<ServerProcess> CappedServer(const TempDir& data) {
  rlimit old_limit{};
  ::getrlimit(RLIMIT_AS, &old_limit);
  rlimit cap = old_limit;
  cap.rlim_cur = std::min<rlim_t>(old_limit.rlim_max, rlim_t{4} << 30);
  ::setrlimit(RLIMIT_AS, &cap);
  auto server = std::make_unique<ServerProcess>(data.path(), std::vector<std::string>{"--shutdown-grace", "2"});
  ::setrlimit(RLIMIT_AS, &old_limit);
  return server;
}

TEST(HostileUploads, AThousandInARowAreAnsweredAndChangeNothing) {
  TempDir data;
  const auto server_process = CappedServer(data);
  ServerProcess& server = *server_process;

  client::ClientOptions o = OptionsFor(server);
  o.timeout = std::chrono::seconds(5);  // beyond the 2 s asserted: a slow answer is measured, a hang cut off
  client::Client client(o);
  client.Import({"arm.bvh", kArmBvh});
  const std::string before = StoredState(client);
  httplib::Client http("127.0.0.1", server.http_port());
  http.set_read_timeout(5);

  // The whole run is bounded too: a server that answers each upload just
  // within its deadline must not keep the suite waiting for an hour.
  RunReport run;
  RunUploads(server, client, http, HostileUploads(kUploads, kSeed), 0,
             std::chrono::steady_clock::now() + std::chrono::seconds(100), run);

  const int64_t peak_kb = StatusKb(server.pid(), "VmHWM");
  std::printf("  %d of %d uploads, slowest answer %.3f s, server peak resident %.1f MB\n", run.done, kUploads,
              run.slowest, static_cast<double>(peak_kb) / 1024);
  for (const auto& [kind, n] : run.imported)
    std::printf("  %d %s uploads still parsed (imported, then deleted)\n", n, kind.c_str());
  EXPECT_TRUE(run.failures.empty()) << run.failures.size() << " kinds of failure:" << run.Failures();
  EXPECT_GT(peak_kb, 0) << "the server is gone";
  EXPECT_LT(peak_kb, kMaxResidentKb) << "peak resident " << peak_kb << " kB";

  // Still serving, and nothing stored changed.
  EXPECT_TRUE(client.Healthy());
  const auto health = http.Get("/healthz");
  EXPECT_TRUE(health && health->status == 200);
  EXPECT_EQ(AssetNames(client), (std::set<std::string>{"arm", "demo_walk", "demo_character"}));
  EXPECT_TRUE(StoredState(client) == before) << "the stored assets changed";
  EXPECT_EQ(server.Stop(SIGTERM, 20), 0) << "no clean exit on SIGTERM";
}

// Repeated on one process, the uploads leave the server's resident memory
// where the first thousand left it (it crept by ~200 MB per thousand, to
// 1.05-1.2 GB from 5,000 on). Each thousand is a new seed: new inputs, same shapes.
TEST(HostileUploads, ResidentMemoryLevelsOffOverThousands) {
  TempDir data;
  const auto server_process = CappedServer(data);
  ServerProcess& server = *server_process;
  client::ClientOptions o = OptionsFor(server);
  o.timeout = std::chrono::seconds(5);
  client::Client client(o);
  httplib::Client http("127.0.0.1", server.http_port());
  http.set_read_timeout(5);
  // ARMATURE_HOSTILE_THOUSANDS runs more (the note's 9,000 were measured so).
  const char* thousands_env = std::getenv("ARMATURE_HOSTILE_THOUSANDS");
  const int kThousands = thousands_env ? std::max(3, std::atoi(thousands_env)) : 3;
  std::vector<int64_t> resident_kb;
  RunReport run;
  const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(100 * kThousands);
  for (int k = 0; k < kThousands; ++k) {
    RunUploads(server, client, http, HostileUploads(kUploads, kSeed + static_cast<uint32_t>(k)), k * kUploads, give_up,
               run);
    resident_kb.push_back(StatusKb(server.pid(), "VmRSS"));
    std::printf("  after %d uploads: resident %.1f MB, peak %.1f MB\n", run.done,
                static_cast<double>(resident_kb.back()) / 1024,
                static_cast<double>(StatusKb(server.pid(), "VmHWM")) / 1024);
  }
  EXPECT_TRUE(run.failures.empty()) << run.failures.size() << " kinds of failure:" << run.Failures();
  ASSERT_EQ(resident_kb.size(), static_cast<size_t>(kThousands));
  // Level: the last thousand adds at most a tenth of what the first left, and 32 MB.
  std::string each;
  for (int64_t kb : resident_kb) each += " " + std::to_string(kb);
  EXPECT_LT(resident_kb.back(), resident_kb.front() + resident_kb.front() / 10 + (32 << 10))
      << "resident after each thousand (kB):" << each;
  EXPECT_EQ(server.Stop(SIGTERM, 20), 0) << "no clean exit on SIGTERM";
}

}  // namespace
}  // namespace armature::testing
