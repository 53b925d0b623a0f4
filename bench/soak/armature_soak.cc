// armature-soak: a bounded soak test of a running armature-server on this
// machine. N clients run a weighted mix of calls for S seconds (both
// bounded), importing and deleting small assets of their own while others
// list. Reports per method the calls, errors by status and p50/p99 latency,
// and the server's resident memory over time (VmRSS of --server-pid).
// Exits 1 if any call failed, 2 on bad flags.
//
//   armature-soak --server 127.0.0.1:50051 --clients 50 --seconds 600 \
//     --mix evaluate=4,stream=1,ik=2,ik_session=1,skin=2,deform=1,list=3,import_delete=1 --server-pid 1234
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <functional>
#include <map>
#include <mutex>
#include <random>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "armature/client.h"

namespace {
using Clock = std::chrono::steady_clock;

// A small BVH for the import/delete churn: one root joint and an End Site,
// turning about Y over `frames` frames.
std::string SmallBvh(int frames) {
  std::ostringstream s;
  s << "HIERARCHY\nROOT Root\n{\n  OFFSET 0 0 0\n"
    << "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n"
    << "  End Site\n  {\n    OFFSET 0 1 0\n  }\n}\nMOTION\nFrames: " << frames << "\nFrame Time: 0.1\n";
  for (int f = 0; f < frames; ++f) s << "0 0 0 0 0 " << 10 * f << "\n";
  return s.str();
}

constexpr int kGrid = 8;  // the deformed mesh: an 8×8 vertex sheet

std::string GridObj() {
  std::ostringstream s;
  for (int j = 0; j < kGrid; ++j)
    for (int i = 0; i < kGrid; ++i) s << "v " << i / double(kGrid - 1) << " " << j / double(kGrid - 1) << " 0\n";
  for (int j = 0; j + 1 < kGrid; ++j)
    for (int i = 0; i + 1 < kGrid; ++i) {
      const int a = j * kGrid + i + 1, b = a + 1, c = a + kGrid, d = c + 1;
      s << "f " << a << " " << b << " " << d << "\nf " << a << " " << d << " " << c << "\n";
    }
  return s.str();
}

// Only this machine may be soaked.
bool IsLoopback(const std::string& target) {
  return target.rfind("127.", 0) == 0 || target.rfind("localhost:", 0) == 0 || target.rfind("[::1]:", 0) == 0;
}

int64_t VmRssKb(int pid) {
  std::ifstream in("/proc/" + std::to_string(pid) + "/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("VmRSS:", 0) == 0) return std::stoll(line.substr(6));
  return -1;
}

// A refusal by an admission limit the soak may run into by design (50
// clients on one address hold more sessions than --max-sessions-per-client
// allows): counted, but not an error.
bool IsExpectedRefusal(const grpc::Status& st) {
  return st.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED &&
         (st.error_message().find("--max-sessions") != std::string::npos ||
          st.error_message().find("--max-ik-sessions") != std::string::npos);
}

struct MethodStats {
  std::vector<double> latencies_ms;
  int refused = 0;  // IsExpectedRefusal
  std::map<std::string, int> errors;  // status code name → count
  std::string first_error;
};

class Stats {
 public:
  void Record(const std::string& method, double ms, const grpc::Status& st) {
    std::lock_guard lock(mu_);
    MethodStats& m = methods_[method];
    m.latencies_ms.push_back(ms);
    if (IsExpectedRefusal(st)) {
      ++m.refused;
    } else if (!st.ok()) {
      if (m.first_error.empty()) m.first_error = st.error_message();
      ++m.errors[armature::StatusCodeName(st.error_code())];
    }
  }
  // Prints the table; returns the number of errors.
  int Report() {
    std::lock_guard lock(mu_);
    int errors = 0;
    std::printf("%-14s %8s %8s %8s %9s %9s  %s\n", "method", "calls", "refused", "errors", "p50 ms", "p99 ms",
                "errors by status");
    for (auto& [name, m] : methods_) {
      std::sort(m.latencies_ms.begin(), m.latencies_ms.end());
      auto pct = [&](double p) {
        return m.latencies_ms.empty() ? 0.0 : m.latencies_ms[static_cast<size_t>(p * (m.latencies_ms.size() - 1))];
      };
      int n = 0;
      std::string by;
      for (const auto& [code, k] : m.errors) {
        n += k;
        by += code + "=" + std::to_string(k) + " ";
      }
      errors += n;
      std::printf("%-14s %8zu %8d %8d %9.2f %9.2f  %s%s\n", name.c_str(), m.latencies_ms.size(), m.refused, n, pct(0.5),
                  pct(0.99),
                  by.c_str(), m.first_error.empty() ? "" : ("(first: " + m.first_error + ")").c_str());
    }
    return errors;
  }

 private:
  std::mutex mu_;
  std::map<std::string, MethodStats> methods_;
};

struct Mix {
  std::vector<std::pair<std::string, int>> weights;
  int total = 0;
};

bool ParseMix(const std::string& text, Mix& mix, std::string& error) {
  static const std::vector<std::string> kKnown = {"evaluate", "stream", "ik",   "ik_session",
                                                  "skin",     "deform", "list", "import_delete"};
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    const auto eq = item.find('=');
    const std::string name = item.substr(0, eq);
    if (std::find(kKnown.begin(), kKnown.end(), name) == kKnown.end()) return error = "unknown mix entry '" + name + "'", false;
    int w = 1;
    try {
      if (eq != std::string::npos) w = std::stoi(item.substr(eq + 1));
    } catch (...) {
      return error = "bad weight in '" + item + "'", false;
    }
    if (w < 0 || w > 1000) return error = "weight out of 0..1000 in '" + item + "'", false;
    mix.weights.emplace_back(name, w);
    mix.total += w;
  }
  if (mix.total == 0) return error = "the mix has no weight", false;
  return true;
}

// One client's loop: weighted random calls until the deadline.
class Worker {
 public:
  Worker(const std::string& target, int id, const Mix& mix, Stats& stats)
      : id_(id), mix_(mix), stats_(stats), rng_(1000 + id) {
    armature::ClientOptions o;
    o.target = target;
    o.timeout = std::chrono::seconds(10);
    o.stream_timeout = std::chrono::seconds(10);
    client_ = std::make_unique<armature::Client>(o);
  }

  void Run(Clock::time_point deadline) {
    while (Clock::now() < deadline) {
      int pick = static_cast<int>(rng_() % mix_.total);
      for (const auto& [name, w] : mix_.weights) {
        if (pick < w) {
          Call(name);
          break;
        }
        pick -= w;
      }
    }
  }

 private:
  void Timed(const std::string& method, const std::function<void()>& call) {
    const auto t0 = Clock::now();
    grpc::Status st = grpc::Status::OK;
    try {
      call();
    } catch (const armature::ClientError& e) {
      st = grpc::Status(e.code(), e.what());
    } catch (const std::exception& e) {
      st = grpc::Status(grpc::StatusCode::UNKNOWN, e.what());
    }
    stats_.Record(method, std::chrono::duration<double, std::milli>(Clock::now() - t0).count(), st);
  }

  double Jitter(double scale) { return scale * (static_cast<double>(rng_() % 1000) / 1000.0 - 0.5); }

  armature::v1::SolveIkRequest IkStart() {
    armature::v1::SolveIkRequest r;
    r.set_skeleton("demo_walk");
    auto* e = r.add_effectors();
    e->set_joint("LeftWrist");
    for (double v : {20 + Jitter(4), 30 + Jitter(4), 20 + Jitter(4)}) e->add_target_position(v);
    return r;
  }

  void Call(const std::string& kind) {
    namespace v1 = armature::v1;
    if (kind == "evaluate") {
      v1::EvaluateClipRequest r;
      r.set_clip("demo_walk");
      for (int k = 0; k < 8; ++k) r.add_times(static_cast<double>(rng_() % 3000) / 1000.0);
      Timed("EvaluateClip", [&] { client_->EvaluateClip(r); });
    } else if (kind == "stream") {
      v1::StreamClipRequest r;
      r.set_clip("demo_walk");
      r.set_fps(60);
      r.set_duration(0.25);
      Timed("StreamClip", [&] { client_->StreamClip(r, [](const v1::PoseFrame&) { return true; }); });
    } else if (kind == "ik") {
      Timed("SolveIk", [&] { client_->SolveIk(IkStart()); });
    } else if (kind == "ik_session") {
      Timed("IkSession", [&] {
        auto session = client_->OpenIkSession(IkStart());
        for (int k = 0; k < 5; ++k) session->MoveTarget(0, 20 + Jitter(6), 30 + Jitter(6), 20 + Jitter(6));
        session->Close();
      });
    } else if (kind == "skin") {
      v1::SkinMeshRequest r;
      r.set_mesh("demo_character.body");
      r.set_clip("demo_character.walk");
      r.set_time(static_cast<double>(rng_() % 3000) / 1000.0);
      Timed("SkinMesh", [&] { client_->SkinMesh(r); });
    } else if (kind == "deform") {
      v1::DeformRequest r;
      r.set_mesh("soak_grid");  // an OBJ's one mesh takes the asset's name
      for (int i = 0; i < kGrid; ++i) r.add_fixed(i);  // the bottom row
      auto* h = r.add_handles();
      h->set_index((kGrid - 1) * kGrid + kGrid / 2);  // the top row's middle
      for (double v : {0.5 + Jitter(0.2), 1.0 + Jitter(0.2), 0.2 + Jitter(0.2)}) h->add_position(v);
      Timed("Deform", [&] { client_->Deform(r); });
    } else if (kind == "list") {
      switch (rng_() % 3) {
        case 0: Timed("ListAssets", [&] { client_->ListAssets(); }); break;
        case 1: Timed("ListClips", [&] { client_->ListClips(); }); break;
        default: Timed("ListSkeletons", [&] { client_->ListSkeletons(); });
      }
    } else if (kind == "import_delete") {
      const std::string name = "soak_c" + std::to_string(id_) + "_" + std::to_string(next_++);
      bool imported = false;
      Timed("ImportAsset", [&] {
        client_->Import({name + ".bvh", SmallBvh(4)}, name);
        imported = true;
      });
      if (imported) Timed("DeleteAsset", [&] { client_->DeleteAsset(name); });
    }
  }

  int id_;
  const Mix& mix_;
  Stats& stats_;
  std::mt19937 rng_;
  std::unique_ptr<armature::Client> client_;
  int next_ = 0;
};

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"armature-soak: a bounded soak test of an armature-server on this machine"};
  std::string server = "127.0.0.1:50051";
  int clients = 50;
  int seconds = 600;
  int server_pid = 0;
  std::string mix_text = "evaluate=4,stream=1,ik=2,ik_session=1,skin=2,deform=1,list=3,import_delete=1";
  app.add_option("--server", server, "gRPC address of the server (loopback only)");
  app.add_option("--clients", clients, "Concurrent clients")->check(CLI::Range(1, 256));
  app.add_option("--seconds", seconds, "How long to run")->check(CLI::Range(1, 3600));
  app.add_option("--mix", mix_text, "Weighted calls: evaluate, stream, ik, ik_session, skin, deform, list, import_delete");
  app.add_option("--server-pid", server_pid, "The server's pid: its VmRSS is sampled each second");
  CLI11_PARSE(app, argc, argv);
  if (!IsLoopback(server)) {
    std::fprintf(stderr, "--server %s: only a server on this machine (127.0.0.0/8, localhost, [::1]) may be soaked\n",
                 server.c_str());
    return 2;
  }
  Mix mix;
  if (std::string error; !ParseMix(mix_text, mix, error)) {
    std::fprintf(stderr, "--mix: %s\n", error.c_str());
    return 2;
  }

  // The deformed sheet is the soak's own asset (replaced if a previous run left it).
  armature::ClientOptions setup_options;
  setup_options.target = server;
  setup_options.timeout = std::chrono::seconds(30);
  try {
    armature::Client setup(setup_options);
    setup.Import({"grid.obj", GridObj()}, "soak_grid", "", true);
  } catch (const armature::ClientError& e) {
    std::fprintf(stderr, "cannot set up (import soak_grid) on %s: %s\n", server.c_str(), e.what());
    return 1;
  }

  Stats stats;
  const auto start = Clock::now();
  const auto deadline = start + std::chrono::seconds(seconds);
  std::atomic<bool> done{false};
  std::vector<std::pair<double, int64_t>> rss;  // seconds since start, kB
  std::thread sampler([&] {
    while (!done) {
      if (server_pid > 0)
        rss.emplace_back(std::chrono::duration<double>(Clock::now() - start).count(), VmRssKb(server_pid));
      for (int k = 0; k < 10 && !done; ++k) std::this_thread::sleep_for(std::chrono::milliseconds(100));
    }
  });
  std::vector<std::unique_ptr<Worker>> workers;
  for (int i = 0; i < clients; ++i) workers.push_back(std::make_unique<Worker>(server, i, mix, stats));
  std::vector<std::thread> threads;
  for (auto& w : workers) threads.emplace_back([&w, deadline] { w->Run(deadline); });
  for (auto& t : threads) t.join();
  done = true;
  sampler.join();
  try {
    armature::Client(setup_options).DeleteAsset("soak_grid");
  } catch (const armature::ClientError&) {
  }

  std::printf("armature-soak: %d clients, %d s against %s\n", clients, seconds, server.c_str());
  const int errors = stats.Report();
  if (!rss.empty()) {
    int64_t lo = rss.front().second, hi = lo;
    for (const auto& [t, kb] : rss) lo = std::min(lo, kb), hi = std::max(hi, kb);
    std::printf("server VmRSS: start %.1f MB, min %.1f MB, max %.1f MB, end %.1f MB\n", rss.front().second / 1024.0,
                lo / 1024.0, hi / 1024.0, rss.back().second / 1024.0);
    const size_t step = std::max<size_t>(1, rss.size() / 10);
    std::printf("server VmRSS over time:");
    for (size_t k = 0; k < rss.size(); k += step) std::printf(" %.0fs=%.1fMB", rss[k].first, rss[k].second / 1024.0);
    std::printf("\n");
  }
  std::printf("%s: %d errors\n", errors == 0 ? "PASS" : "FAIL", errors);
  return errors == 0 ? 0 : 1;
}
