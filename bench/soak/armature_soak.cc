// armature-soak: a bounded soak test of a running armature-server on this
// machine. N clients run a weighted mix of calls for S seconds (both
// bounded), importing and deleting small assets of their own while others
// list. Reports per method the calls, errors by status and p50/p99 latency,
// and the server's resident memory over time (VmRSS of --server-pid).
// Exits 1 if any call failed, 2 on bad flags.
//
//   armature-soak --server 127.0.0.1:50051 --http-port 8080 --clients 50 --seconds 600 --server-pid 1234
//
// The calls (soak_worker.h) and those through the HTTP port (soak_http.h)
// live apart; the tally is soak_stats.h.
#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include <CLI/CLI.hpp>

#include "armature/client.h"
#include "soak_worker.h"

namespace {
using Clock = std::chrono::steady_clock;
using armature::soak::Mix;

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

bool ParseMix(const std::string& text, Mix& mix, std::string& error) {
  const auto& known = armature::soak::MixEntries();
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    const auto eq = item.find('=');
    const std::string name = item.substr(0, eq);
    if (std::find(known.begin(), known.end(), name) == known.end())
      return error = "unknown mix entry '" + name + "'", false;
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

void ReportRss(const std::vector<std::pair<double, int64_t>>& rss) {
  if (rss.empty()) return;
  int64_t lo = rss.front().second, hi = lo;
  for (const auto& [t, kb] : rss) lo = std::min(lo, kb), hi = std::max(hi, kb);
  std::printf("server VmRSS: start %.1f MB, min %.1f MB, max %.1f MB, end %.1f MB\n", rss.front().second / 1024.0,
              lo / 1024.0, hi / 1024.0, rss.back().second / 1024.0);
  const size_t step = std::max<size_t>(1, rss.size() / 10);
  std::printf("server VmRSS over time:");
  for (size_t k = 0; k < rss.size(); k += step) std::printf(" %.0fs=%.1fMB", rss[k].first, rss[k].second / 1024.0);
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"armature-soak: a bounded soak test of an armature-server on this machine"};
  std::string server = "127.0.0.1:50051";
  int http_port = 0;
  int clients = 50;
  int seconds = 600;
  int server_pid = 0;
  std::string mix_text =
      "evaluate=4,stream=1,ik=2,ik_session=1,skin=2,deform=1,list=3,import_delete=1,motion=1,bake=1,export=1,"
      "character=1,retarget=1,playback=1,ws_session=1,grpc_web=1,rest_binary=1";
  app.add_option("--server", server, "gRPC address of the server (loopback only)");
  app.add_option("--http-port", http_port,
                 "The server's HTTP port on the same host, for gRPC-Web, binary REST and WebSocket sessions "
                 "(0: those entries of the mix are skipped)")
      ->check(CLI::Range(0, 65535));
  app.add_option("--clients", clients, "Concurrent clients")->check(CLI::Range(1, 256));
  app.add_option("--seconds", seconds, "How long to run")->check(CLI::Range(1, 3600));
  std::string entries;
  for (const auto& e : armature::soak::MixEntries()) entries += (entries.empty() ? "" : ", ") + e;
  app.add_option("--mix", mix_text, "Weighted calls: " + entries);
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
  armature::client::ClientOptions setup_options;
  setup_options.target = server;
  setup_options.timeout = std::chrono::seconds(30);
  try {
    armature::client::Client setup(setup_options);
    setup.Import({"grid.obj", armature::soak::GridObj()}, "soak_grid", "", true);
  } catch (const armature::client::ClientError& e) {
    std::fprintf(stderr, "cannot set up (import soak_grid) on %s: %s\n", server.c_str(), e.what());
    return 1;
  }

  armature::soak::Stats stats;
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
  std::vector<std::unique_ptr<armature::soak::Worker>> workers;
  for (int i = 0; i < clients; ++i)
    workers.push_back(std::make_unique<armature::soak::Worker>(server, http_port, i, mix, stats));
  std::vector<std::thread> threads;
  for (auto& w : workers) threads.emplace_back([&w, deadline] { w->Run(deadline); });
  for (auto& t : threads) t.join();
  done = true;
  sampler.join();
  try {
    armature::client::Client(setup_options).DeleteAsset("soak_grid");
  } catch (const armature::client::ClientError&) {}

  std::printf("armature-soak: %d clients, %d s against %s (HTTP port %d)\n", clients, seconds, server.c_str(),
              http_port);
  const int errors = stats.Report();
  ReportRss(rss);
  std::printf("%s: %d errors\n", errors == 0 ? "PASS" : "FAIL", errors);
  return errors == 0 ? 0 : 1;
}
