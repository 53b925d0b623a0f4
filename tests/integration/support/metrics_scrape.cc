#include "metrics_scrape.h"

#include <cmath>
#include <sstream>

#include <gtest/gtest.h>

#include "http_get.h"

namespace armature::testing {

std::map<std::string, double> ParseSamples(const std::string& text) {
  std::map<std::string, double> samples;
  std::istringstream lines(text);
  for (std::string line; std::getline(lines, line);) {
    if (line.empty() || line[0] == '#') continue;
    const auto space = line.rfind(' ');
    samples[line.substr(0, space)] = line.substr(space + 1) == "+Inf" ? INFINITY : std::stod(line.substr(space + 1));
  }
  return samples;
}

std::map<std::string, double> Scrape(const ServerProcess& server) {
  const HttpResponse r = HttpGet("http://127.0.0.1:" + std::to_string(server.http_port()) + "/metrics");
  EXPECT_EQ(r.status, 200) << r.error;
  return r.status == 200 ? ParseSamples(r.body) : std::map<std::string, double>{};
}

double ScrapeSample(const ServerProcess& server, const std::string& sample) {
  const auto samples = Scrape(server);
  const auto it = samples.find(sample);
  return it == samples.end() ? -1 : it->second;
}

}  // namespace armature::testing
