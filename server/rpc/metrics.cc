#include "server/rpc/metrics.h"

#include <charconv>
#include <cmath>

#include "armature/build_info.h"

namespace armature::server {
namespace {

void AppendNumber(std::string& out, double v) {
  if (std::isnan(v)) {
    out += "NaN";
  } else if (std::isinf(v)) {
    out += v > 0 ? "+Inf" : "-Inf";
  } else {
    char buf[32];
    const auto [end, ec] =
        std::to_chars(buf, buf + sizeof buf, v, std::chars_format::general);  // shortest, 0.0005 not 5e-04
    out.append(buf, end);
  }
}

void AppendEscaped(std::string& out, std::string_view value) {
  for (char c : value) {
    if (c == '\\')
      out += "\\\\";
    else if (c == '"')
      out += "\\\"";
    else if (c == '\n')
      out += "\\n";
    else
      out += c;
  }
}

}  // namespace

void PrometheusText::Family(std::string_view name, std::string_view type, std::string_view help) {
  out_.append("# HELP ").append(name).append(" ");
  for (char c : help) out_ += c == '\n' ? ' ' : c;
  out_.append("\n# TYPE ").append(name).append(" ").append(type).append("\n");
}

void PrometheusText::Sample(std::string_view name, const Labels& labels, double value) {
  out_.append(name);
  if (!labels.empty()) {
    out_ += '{';
    for (size_t i = 0; i < labels.size(); ++i) {
      if (i) out_ += ',';
      out_.append(labels[i].first).append("=\"");
      AppendEscaped(out_, labels[i].second);
      out_ += '"';
    }
    out_ += '}';
  }
  out_ += ' ';
  AppendNumber(out_, value);
  out_ += '\n';
}

Metrics::MethodStats& Metrics::StatsOf(std::string_view method) {
  auto it = methods_.find(method);
  if (it == methods_.end()) it = methods_.emplace(std::string(method), MethodStats{}).first;
  return it->second;
}

void Metrics::RpcStarted(std::string_view method, bool streaming) {
  std::lock_guard lock(mu_);
  ++StatsOf(method).in_flight;
  if (streaming) ++streams_in_flight_;
}

void Metrics::RpcFinished(std::string_view method, bool streaming, std::string_view code, double seconds) {
  size_t bucket = 0;
  while (bucket < kBuckets.size() && seconds > kBuckets[bucket]) ++bucket;
  std::lock_guard lock(mu_);
  MethodStats& m = StatsOf(method);
  --m.in_flight;
  if (streaming) --streams_in_flight_;
  ++m.buckets[bucket];
  m.sum += seconds;
  ++m.count;
  auto c = m.codes.find(code);
  if (c == m.codes.end()) c = m.codes.emplace(std::string(code), 0).first;
  ++c->second;
}

void Metrics::AddCollector(std::function<void(PrometheusText&)> collect) {
  std::lock_guard lock(mu_);
  collectors_.push_back(std::move(collect));
}

std::string Metrics::Render() const {
  PrometheusText out;
  std::vector<std::function<void(PrometheusText&)>> collectors;
  {
    std::lock_guard lock(mu_);
    out.Family("armature_rpc_duration_seconds", "histogram",
               "Time from a call's arrival to its status, by gRPC method (REST calls included).");
    for (const auto& [method, m] : methods_) {
      uint64_t cumulative = 0;
      for (size_t b = 0; b <= kBuckets.size(); ++b) {
        cumulative += m.buckets[b];
        std::string le;
        AppendNumber(le, b < kBuckets.size() ? kBuckets[b] : INFINITY);
        out.Sample("armature_rpc_duration_seconds_bucket", {{"method", method}, {"le", le}},
                   static_cast<double>(cumulative));
      }
      out.Sample("armature_rpc_duration_seconds_sum", {{"method", method}}, m.sum);
      out.Sample("armature_rpc_duration_seconds_count", {{"method", method}}, static_cast<double>(m.count));
    }
    out.Family("armature_rpc_requests_total", "counter", "Finished calls by gRPC method and status code.");
    for (const auto& [method, m] : methods_)
      for (const auto& [code, n] : m.codes)
        out.Sample("armature_rpc_requests_total", {{"method", method}, {"code", code}}, static_cast<double>(n));
    out.Family("armature_rpc_in_flight", "gauge", "Calls started and not yet finished, by gRPC method.");
    for (const auto& [method, m] : methods_)
      out.Sample("armature_rpc_in_flight", {{"method", method}}, static_cast<double>(m.in_flight));
    out.Family("armature_streams_in_flight", "gauge", "Streaming calls (client, server or bidi) now open.");
    out.Sample("armature_streams_in_flight", {}, static_cast<double>(streams_in_flight_));
    // The usual info-metric idiom: always 1, the facts are in the labels.
    out.Family("armature_build_info", "gauge", "The server's version and git commit (value always 1).");
    out.Sample("armature_build_info", {{"version", build_info::kVersion}, {"commit", build_info::kCommit}}, 1);
    collectors = collectors_;
  }
  for (const auto& collect : collectors) collect(out);
  return out.text();
}

}  // namespace armature::server
