#include "soak_stats.h"

#include <algorithm>
#include <cstdio>

#include "armature/client.h"

namespace armature::soak {

bool IsExpectedRefusal(const grpc::Status& st) {
  return st.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED &&
         (st.error_message().find("--max-sessions") != std::string::npos ||
          st.error_message().find("--max-ik-sessions") != std::string::npos ||
          st.error_message().find("--max-concurrent-uploads") != std::string::npos);
}

void Stats::Record(const std::string& method, double ms, const grpc::Status& st) {
  std::lock_guard lock(mu_);
  MethodStats& m = methods_[method];
  m.latencies_ms.push_back(ms);
  if (IsExpectedRefusal(st)) {
    ++m.refused;
  } else if (!st.ok()) {
    if (m.first_error.empty()) m.first_error = st.error_message();
    ++m.errors[client::StatusCodeName(st.error_code())];
  }
}

int Stats::Report() {
  std::lock_guard lock(mu_);
  int errors = 0;
  std::printf("%-16s %8s %8s %8s %9s %9s  %s\n", "method", "calls", "refused", "errors", "p50 ms", "p99 ms",
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
    std::printf("%-16s %8zu %8d %8d %9.2f %9.2f  %s%s\n", name.c_str(), m.latencies_ms.size(), m.refused, n, pct(0.5),
                pct(0.99), by.c_str(), m.first_error.empty() ? "" : ("(first: " + m.first_error + ")").c_str());
  }
  return errors;
}

}  // namespace armature::soak
