// armature-load: a closed-loop load generator for an armature-server on this
// machine (loopback targets only), gRPC callback API.
//
// Unary mode: for each --concurrency, alternates --rounds phases of the
// baseline (grpc.health.v1.Health/Check) and of the --rpc mix, each
// --seconds/--rounds long, and prints calls/s and p50/p99/p999 latency of
// both and the ratio of their throughputs (both measured in the same run, so
// the machine's other load hits both alike).
//
//   armature-load --target 127.0.0.1:50051 --import-bvh cmu_01_01.bvh --rpc evaluate --concurrency 1,8,32,128
//
// Stream mode (--streams 100,500,1000): N StreamClip streams at --fps from
// this process; reports the inter-frame arrival interval (mean, p99, max
// deviation from 1/fps), frames late or lost, and the CPU of --server-pid.
//
// Crowd mode (--crowds 1x10000,100x100): SESSIONS CrowdSession calls of
// CHARACTERS each at --fps; reports the mean tick interval against 1/fps
// (arrival and the server's own clock), late ticks, deferred characters,
// wire bytes per joint, and server CPU per character-tick (--server-pid).
//
// Exits 1 when a call failed or nothing completed, 2 on bad flags.
#include <cstdio>
#include <sstream>

#include <CLI/CLI.hpp>

#include "armature/client.h"
#include "crowd_scale.h"
#include "load_target.h"
#include "proc_cpu.h"
#include "stream_scale.h"
#include "unary_load.h"

namespace {

using namespace armature_load;

bool ParseList(const std::string& text, int lo, int hi, std::vector<int>& out) {
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    try {
      size_t used = 0;
      const int v = std::stoi(item, &used);
      if (used != item.size() || v < lo || v > hi) return false;
      out.push_back(v);
    } catch (...) {
      return false;
    }
  }
  return !out.empty();
}

bool ParseMix(const std::string& text, std::vector<MixEntry>& mix, std::string& error) {
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    const auto eq = item.find('=');
    MixEntry e{Rpc::kHealth, 1};
    if (!RpcFromName(item.substr(0, eq), e.rpc)) return error = "unknown RPC '" + item.substr(0, eq) + "'", false;
    try {
      if (eq != std::string::npos) e.weight = std::stoi(item.substr(eq + 1));
    } catch (...) {
      return error = "bad weight in '" + item + "'", false;
    }
    if (e.weight < 1 || e.weight > 1000) return error = "weight out of 1..1000 in '" + item + "'", false;
    mix.push_back(e);
  }
  if (mix.empty()) return error = "no RPC given", false;
  return true;
}

std::vector<std::shared_ptr<grpc::Channel>> Channels(const std::string& target, int n, int window_kb, int read_kb) {
  std::vector<std::shared_ptr<grpc::Channel>> channels;
  for (int i = 0; i < n; ++i) {
    grpc::ChannelArguments args;
    args.SetInt(GRPC_ARG_USE_LOCAL_SUBCHANNEL_POOL, 1);  // a connection of its own per channel
    args.SetInt("armature.load.channel", i);
    args.SetMaxReceiveMessageSize(64 << 20);
    if (window_kb > 0) args.SetInt(GRPC_ARG_HTTP2_STREAM_LOOKAHEAD_BYTES, window_kb << 10);
    if (read_kb > 0) args.SetInt(GRPC_ARG_TCP_MIN_READ_CHUNK_SIZE, read_kb << 10);
    channels.push_back(grpc::CreateCustomChannel(target, grpc::InsecureChannelCredentials(), args));
  }
  return channels;
}

struct Totals {
  RpcOutcome outcome;
  double seconds = 0;
};

void PrintRow(const std::string& name, Totals& t) {
  const Percentiles p = Summarize(t.outcome.latencies_ms);
  std::printf("  %-34s %9zu %10.0f %9.3f %9.3f %9.3f %7lld%s%s\n", name.c_str(), p.count,
              t.seconds > 0 ? static_cast<double>(p.count) / t.seconds : 0.0, p.p50, p.p99, p.p999,
              static_cast<long long>(t.outcome.errors),
              t.outcome.first_error.empty() ? "" : "  first error: ", t.outcome.first_error.c_str());
}

// One concurrency point; returns false when a call failed or none completed.
bool RunUnaryPoint(const std::vector<std::shared_ptr<grpc::Channel>>& channels, const std::vector<MixEntry>& mix,
                   const CallShape& shape, int concurrency, double seconds, int rounds, const std::string& mix_text,
                   int server_pid) {
  const std::vector<MixEntry> baseline = {{Rpc::kHealth, 1}};
  std::map<Rpc, Totals> base, load;
  double base_seconds = 0, load_seconds = 0;
  // CPU seconds of the server and of this process per side: CPU per call is
  // far steadier than calls/s on a machine others share.
  double server_cpu[2] = {0, 0}, client_cpu[2] = {0, 0};
  for (int r = 0; r < rounds; ++r) {
    for (int side = 0; side < 2; ++side) {
      const double s0 = server_pid > 0 ? ProcessCpuSeconds(server_pid) : 0, c0 = ProcessCpuSeconds(0);
      PhaseOutcome phase = RunClosedLoop(channels, side == 0 ? baseline : mix, shape, concurrency, seconds / rounds);
      server_cpu[side] += (server_pid > 0 ? ProcessCpuSeconds(server_pid) : 0) - s0;
      client_cpu[side] += ProcessCpuSeconds(0) - c0;
      auto& into = side == 0 ? base : load;
      (side == 0 ? base_seconds : load_seconds) += phase.seconds;
      for (auto& [rpc, o] : phase.by_rpc) {
        RpcOutcome& t = into[rpc].outcome;
        t.latencies_ms.insert(t.latencies_ms.end(), o.latencies_ms.begin(), o.latencies_ms.end());
        if (t.errors == 0) t.first_error = o.first_error;
        t.errors += o.errors;
      }
    }
  }
  std::printf("concurrency %d: %.1f s of each side in %d alternating round(s), %zu connection(s)\n", concurrency,
              seconds, rounds, channels.size());
  std::printf("  %-34s %9s %10s %9s %9s %9s %7s\n", "rpc", "calls", "calls/s", "p50 ms", "p99 ms", "p999 ms", "errors");
  Totals& health = base[Rpc::kHealth];
  health.seconds = base_seconds;
  const int64_t health_calls = static_cast<int64_t>(health.outcome.latencies_ms.size());
  bool ok = health_calls > 0 && health.outcome.errors == 0;
  PrintRow("grpc.health.v1.Health/Check (base)", health);
  int64_t load_calls = 0, load_errors = 0;
  for (auto& [rpc, t] : load) {
    t.seconds = load_seconds;
    load_calls += static_cast<int64_t>(t.outcome.latencies_ms.size());
    load_errors += t.outcome.errors;
    PrintRow(RpcLabel(rpc), t);
  }
  ok = ok && load_calls > 0 && load_errors == 0;
  const double base_rate = base_seconds > 0 ? health_calls / base_seconds : 0;
  const double load_rate = load_seconds > 0 ? load_calls / load_seconds : 0;
  const double ratio = base_rate > 0 ? load_rate / base_rate : 0;
  std::printf("  throughput of '%s' / health check: %.3f\n", mix_text.c_str(), ratio);
  const auto per_call_us = [](double cpu, int64_t calls) { return calls > 0 ? 1e6 * cpu / calls : 0.0; };
  const double server_us[2] = {per_call_us(server_cpu[0], health_calls), per_call_us(server_cpu[1], load_calls)};
  const double client_us[2] = {per_call_us(client_cpu[0], health_calls), per_call_us(client_cpu[1], load_calls)};
  if (server_pid > 0)
    std::printf("  CPU per call, server: health %.1f us, '%s' %.1f us (%.2fx); this client: %.1f us, %.1f us\n",
                server_us[0], mix_text.c_str(), server_us[1], server_us[0] > 0 ? server_us[1] / server_us[0] : 0.0,
                client_us[0], client_us[1]);
  // One line for scripts.
  std::printf(
      "RESULT mode=unary rpc=%s concurrency=%d calls_per_s=%.1f health_calls_per_s=%.1f ratio=%.4f errors=%lld "
      "server_cpu_us_health=%.2f server_cpu_us=%.2f\n",
      mix_text.c_str(), concurrency, load_rate, base_rate, ratio, static_cast<long long>(load_errors), server_us[0],
      server_us[1]);
  return ok;
}

// "SxC,SxC": sessions × characters per point.
bool ParseCrowds(const std::string& text, std::vector<std::pair<int, int>>& out) {
  std::istringstream in(text);
  for (std::string item; std::getline(in, item, ',');) {
    const auto x = item.find('x');
    std::vector<int> sessions, characters;
    if (x == std::string::npos || !ParseList(item.substr(0, x), 1, 10000, sessions) ||
        !ParseList(item.substr(x + 1), 1, 100000, characters))
      return false;
    out.emplace_back(sessions[0], characters[0]);
  }
  return !out.empty();
}

bool RunCrowdPoint(const std::vector<std::shared_ptr<grpc::Channel>>& channels, const CrowdScaleOptions& o) {
  const CrowdScaleOutcome r = RunCrowdScale(channels, o);
  const double period = 1000.0 / o.fps;
  std::printf(
      "%d crowd(s) of %d characters at %.0f fps over %zu connection(s): all first frames in %.2f s, window "
      "%.2f s\n",
      o.sessions, o.characters, o.fps, channels.size(), r.open_seconds, r.window_seconds);
  std::printf("  tick interval ms: arrival mean %.3f (%.4f of 1/fps) p99 %.3f; server mean %.3f (%.4f) p99 %.3f\n",
              r.interval_ms.mean, r.interval_ms.mean / period, r.interval_ms.p99, r.server_interval_ms.mean,
              r.server_interval_ms.mean / period, r.server_interval_ms.p99);
  std::printf(
      "  frames %lld of %lld due, late ticks %lld; per tick (all crowds): %.0f poses sent, %.0f characters "
      "deferred; %.2f wire bytes a joint\n",
      static_cast<long long>(r.frames), static_cast<long long>(r.frames_expected), static_cast<long long>(r.late_ticks),
      r.updated_per_tick, r.deferred_per_tick, r.wire_bytes_per_joint);
  std::printf(
      "  server CPU %.1f %% of a core (%.3f us a pose sent, %.3f us a character-tick), this client %.1f %%; "
      "crowds failed %d%s%s\n",
      r.server_cpu_percent, r.server_cpu_us_per_update, r.server_cpu_us_per_character_tick, r.client_cpu_percent,
      r.sessions_failed, r.first_error.empty() ? "" : ", first error: ", r.first_error.c_str());
  std::printf(
      "RESULT mode=crowds sessions=%d characters=%d fps=%.0f interval_mean_ms=%.3f interval_ratio=%.4f "
      "server_interval_mean_ms=%.3f server_interval_ratio=%.4f frames=%lld expected=%lld late=%lld "
      "updated_per_tick=%.1f deferred_per_tick=%.1f wire_bytes_per_joint=%.3f server_cpu_pct=%.1f "
      "server_cpu_us_per_update=%.4f server_cpu_us_per_character_tick=%.4f failed=%d\n",
      o.sessions, o.characters, o.fps, r.interval_ms.mean, r.interval_ms.mean / period, r.server_interval_ms.mean,
      r.server_interval_ms.mean / period, static_cast<long long>(r.frames), static_cast<long long>(r.frames_expected),
      static_cast<long long>(r.late_ticks), r.updated_per_tick, r.deferred_per_tick, r.wire_bytes_per_joint,
      r.server_cpu_percent, r.server_cpu_us_per_update, r.server_cpu_us_per_character_tick, r.sessions_failed);
  return r.sessions_failed == 0 && r.sessions_opened == o.sessions && r.frames > 0;
}

bool RunStreamPoint(const std::vector<std::shared_ptr<grpc::Channel>>& channels, StreamScaleOptions o) {
  const StreamScaleOutcome r = RunStreamScale(channels, o);
  std::printf("%d streams at %.0f fps over %zu connection(s): all first frames in %.2f s, window %.2f s\n", o.streams,
              o.fps, channels.size(), r.open_seconds, r.window_seconds);
  std::printf("  interval ms: mean %.3f  p50 %.3f  p99 %.3f  min..max jitter: |dev| p50 %.3f  p99 %.3f  max %.3f\n",
              r.interval_ms.mean, r.interval_ms.p50, r.interval_ms.p99, r.deviation_ms.p50, r.deviation_ms.p99,
              r.deviation_ms.max);
  std::printf(
      "  worst stream's p99 |dev| %.3f ms; frames %lld of %lld due, lost %lld, late (> %.1f ms) %lld, "
      "latest %.1f ms\n",
      r.worst_stream_p99_deviation_ms, static_cast<long long>(r.frames), static_cast<long long>(r.frames_expected),
      static_cast<long long>(r.frames_lost), o.late_ms, static_cast<long long>(r.frames_late), r.max_late_ms);
  std::printf("  server-side lateness (wall_time - index/fps) ms: p50 %.3f  p99 %.3f  max %.3f\n", r.server_late_ms.p50,
              r.server_late_ms.p99, r.server_late_ms.max);
  std::printf("  server CPU %.1f %% of a core, this client %.1f %%; streams failed %d%s%s\n", r.server_cpu_percent,
              r.client_cpu_percent, r.streams_failed,
              r.first_error.empty() ? "" : ", first error: ", r.first_error.c_str());
  std::printf(
      "RESULT mode=streams streams=%d fps=%.0f interval_mean_ms=%.3f jitter_p99_ms=%.3f jitter_max_ms=%.3f "
      "frames=%lld expected=%lld lost=%lld late=%lld server_late_p99_ms=%.3f server_cpu_pct=%.1f client_cpu_pct=%.1f "
      "failed=%d\n",
      o.streams, o.fps, r.interval_ms.mean, r.deviation_ms.p99, r.deviation_ms.max, static_cast<long long>(r.frames),
      static_cast<long long>(r.frames_expected), static_cast<long long>(r.frames_lost),
      static_cast<long long>(r.frames_late), r.server_late_ms.p99, r.server_cpu_percent, r.client_cpu_percent,
      r.streams_failed);
  return r.streams_failed == 0 && r.streams_opened == o.streams && r.frames > 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"armature-load: closed-loop load on an armature-server on this machine"};
  std::string target = "127.0.0.1:50051", rpc_text = "evaluate", concurrency_text = "1,8,32,128", streams_text;
  std::string import_bvh, crowds_text;
  CrowdScaleOptions crowd;  // its budget and sharing from flags; the rest per point
  double seconds = 5, fps = 60, warmup = 1, late_ms = 5;
  int rounds = 2, connections = 1, server_pid = 0, window_kb = 0, read_kb = 0;
  CallShape shape;
  app.add_option("--target", target, "gRPC address of the server (loopback only: 127.0.0.0/8, localhost, [::1])");
  app.add_option("--rpc", rpc_text, "RPC or weighted mix: health, evaluate, skin, stream (e.g. evaluate=4,skin=1)");
  app.add_option("--concurrency", concurrency_text, "Calls in flight, one point per value (e.g. 1,8,32,128)");
  app.add_option("--seconds", seconds, "Measured seconds per point (unary: of each side)")
      ->check(CLI::Range(0.1, 3600.0));
  app.add_option("--rounds", rounds, "Unary: alternating baseline/mix phases per point")->check(CLI::Range(1, 100));
  app.add_option("--connections", connections, "gRPC connections, calls spread over them")->check(CLI::Range(1, 64));
  app.add_option("--window-kb", window_kb, "HTTP/2 receive window per stream (lookahead), KiB; 0 = gRPC's")
      ->check(CLI::Range(0, 65536));
  app.add_option("--read-chunk-kb", read_kb, "Least TCP read size, KiB; 0 = gRPC's")->check(CLI::Range(0, 65536));
  app.add_option("--import-bvh", import_bvh, "Import this BVH first, as --clip (replacing it)");
  app.add_option("--clip", shape.clip, "Clip of EvaluateClip (one pose) and StreamClip");
  app.add_option("--mesh", shape.mesh, "Mesh of SkinMesh");
  app.add_option("--mesh-clip", shape.mesh_clip, "Clip of SkinMesh");
  app.add_option("--streams", streams_text,
                 "Stream mode: StreamClip streams at once, one point per value (e.g. 100,500,1000)");
  app.add_option("--crowds", crowds_text,
                 "Crowd mode: SESSIONSxCHARACTERS CrowdSession calls, one point per value (e.g. 1x10000,100x100)");
  app.add_option("--budget-ms", crowd.budget_ms, "Crowd mode: each crowd's tick budget; 0 = the server's")
      ->check(CLI::Range(0.0, 1000.0));
  app.add_option("--share-quantum", crowd.share_quantum,
                 "Crowd mode: clip times rounded to this to share samples; 0 = the server's 1/120 s, -1 = no sharing")
      ->check(CLI::Range(-1.0, 1.0));
  app.add_option("--fps", fps, "Stream and crowd modes: frames per second of each stream")
      ->check(CLI::Range(1.0, 240.0));
  app.add_option("--warmup", warmup, "Stream mode: seconds after every stream plays before measuring")
      ->check(CLI::Range(0.0, 60.0));
  app.add_option("--late-ms", late_ms, "Stream mode: a frame this much past its due time is late")
      ->check(CLI::Range(0.1, 1000.0));
  app.add_option("--server-pid", server_pid,
                 "The server's pid, for its CPU from /proc/<pid>/stat (per call; per stream window)");
  CLI11_PARSE(app, argc, argv);
  if (!IsLoopbackTarget(target)) {
    std::fprintf(stderr,
                 "--target %s: refused, only a server on this machine (127.0.0.0/8, localhost, [::1]) may be loaded\n",
                 target.c_str());
    return 2;
  }
  std::vector<MixEntry> mix;
  std::string error;
  if (!ParseMix(rpc_text, mix, error)) return std::fprintf(stderr, "--rpc: %s\n", error.c_str()), 2;
  std::vector<int> concurrencies, stream_counts;
  if (!ParseList(concurrency_text, 1, 4096, concurrencies))
    return std::fprintf(stderr, "--concurrency: a comma-separated list of 1..4096\n"), 2;
  if (!streams_text.empty() && !ParseList(streams_text, 1, 20000, stream_counts))
    return std::fprintf(stderr, "--streams: a comma-separated list of 1..20000\n"), 2;
  std::vector<std::pair<int, int>> crowds;
  if (!crowds_text.empty() && !ParseCrowds(crowds_text, crowds))
    return std::fprintf(stderr, "--crowds: a comma-separated list of SESSIONSxCHARACTERS (e.g. 1x10000)\n"), 2;

  if (!import_bvh.empty()) {
    armature::client::ClientOptions o;
    o.target = target;
    try {
      armature::client::Client(o).ImportFile(import_bvh, shape.clip, /*replace=*/true);
    } catch (const std::exception& e) {
      return std::fprintf(stderr, "--import-bvh %s: %s\n", import_bvh.c_str(), e.what()), 1;
    }
  }
  const auto channels = Channels(target, connections, window_kb, read_kb);
  bool ok = true;
  if (!crowds.empty()) {
    for (const auto& [sessions, characters] : crowds) {
      CrowdScaleOptions o = crowd;
      o.sessions = sessions;
      o.characters = characters;
      o.fps = fps;
      o.seconds = seconds;
      o.warmup_seconds = warmup;
      o.clip = shape.clip;
      o.server_pid = server_pid;
      ok = RunCrowdPoint(channels, o) && ok;
    }
  } else if (!stream_counts.empty()) {
    for (int n : stream_counts) {
      StreamScaleOptions o;
      o.streams = n;
      o.fps = fps;
      o.seconds = seconds;
      o.warmup_seconds = warmup;
      o.late_ms = late_ms;
      o.clip = shape.clip;
      o.server_pid = server_pid;
      ok = RunStreamPoint(channels, o) && ok;
    }
  } else {
    for (int c : concurrencies)
      ok = RunUnaryPoint(channels, mix, shape, c, seconds, rounds, rpc_text, server_pid) && ok;
  }
  std::fflush(stdout);
  return ok ? 0 : 1;
}
