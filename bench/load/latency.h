// Percentiles of recorded samples (nearest rank on the sorted values).
#pragma once

#include <algorithm>
#include <cmath>
#include <vector>

namespace armature_load {

struct Percentiles {
  size_t count = 0;
  double mean = 0, p50 = 0, p99 = 0, p999 = 0, max = 0;
};

// Sorts `v` in place.
inline Percentiles Summarize(std::vector<double>& v) {
  Percentiles p;
  p.count = v.size();
  if (v.empty()) return p;
  std::sort(v.begin(), v.end());
  auto at = [&](double q) {
    const size_t rank = static_cast<size_t>(std::ceil(q * static_cast<double>(v.size())));
    return v[std::min(v.size() - 1, rank == 0 ? 0 : rank - 1)];
  };
  double sum = 0;
  for (double x : v) sum += x;
  p.mean = sum / static_cast<double>(v.size());
  p.p50 = at(0.5);
  p.p99 = at(0.99);
  p.p999 = at(0.999);
  p.max = v.back();
  return p;
}

}  // namespace armature_load
