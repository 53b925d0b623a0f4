// Reading /metrics (Prometheus text format) in tests.
#pragma once

#include <map>
#include <string>

#include "server_process.h"

namespace armature::testing {

// Samples of a scrape: "name{labels}" → value, labels as written by the server.
std::map<std::string, double> ParseSamples(const std::string& text);

// GET /metrics of `server`, parsed (a failed GET fails the test and gives no samples).
std::map<std::string, double> Scrape(const ServerProcess& server);

// One sample of a fresh scrape, e.g. `armature_sessions_active{kind="ik"}`; -1 when absent.
double ScrapeSample(const ServerProcess& server, const std::string& sample);

}  // namespace armature::testing
