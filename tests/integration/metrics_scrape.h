// Reading the server's /metrics (Prometheus text format) in tests.
#pragma once

#include <map>
#include <string>

#include "server_process.h"

namespace armature::testing {

// Samples of a scrape: "name{labels}" → value, labels as written by the server.
std::map<std::string, double> ParseMetricSamples(const std::string& text);

// GET /metrics from `server` (a failed GET fails the test), parsed.
std::map<std::string, double> ScrapeMetrics(const ServerProcess& server);

}  // namespace armature::testing
