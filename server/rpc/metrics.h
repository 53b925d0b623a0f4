// The server's Prometheus metrics and their text exposition format (0.0.4),
// written here rather than with a client library: a few counters, gauges
// and one histogram family.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <mutex>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace armature::server {

// Writes metric families in the text format: one HELP/TYPE header per
// family, then its samples. Label values are escaped.
class PrometheusText {
 public:
  using Labels = std::vector<std::pair<std::string_view, std::string_view>>;

  void Family(std::string_view name, std::string_view type, std::string_view help);
  void Sample(std::string_view name, const Labels& labels, double value);
  const std::string& text() const { return out_; }

 private:
  std::string out_;
};

class Metrics {
 public:
  // Upper bounds of the latency histogram buckets, in seconds (+Inf is implied).
  static constexpr std::array<double, 16> kBuckets = {0.0005, 0.001, 0.0025, 0.005, 0.01, 0.025, 0.05, 0.1,
                                                      0.25,   0.5,   1,      2.5,   5,    10,    30,   60};

  // A call began; `streaming` for client, server and bidi streams.
  void RpcStarted(std::string_view method, bool streaming);
  // The call ended with `code` (a gRPC code name such as "OK") after `seconds`.
  void RpcFinished(std::string_view method, bool streaming, std::string_view code, double seconds);

  // Further families computed at scrape time (e.g. the asset store's gauges).
  void AddCollector(std::function<void(PrometheusText&)> collect);

  // Everything, in the text format.
  std::string Render() const;

 private:
  struct MethodStats {
    std::array<uint64_t, kBuckets.size() + 1> buckets{};  // per bucket (not cumulative); last is +Inf
    double sum = 0;
    uint64_t count = 0;
    int64_t in_flight = 0;
    std::map<std::string, uint64_t, std::less<>> codes;
  };
  // The method's stats, made on its first call; mu_ must be held.
  MethodStats& StatsOf(std::string_view method);

  mutable std::mutex mu_;
  std::map<std::string, MethodStats, std::less<>> methods_;
  int64_t streams_in_flight_ = 0;
  std::vector<std::function<void(PrometheusText&)>> collectors_;
};

}  // namespace armature::server
