#include "armature/engine/anim/compression/error_bound.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>
#include <vector>

namespace armature {

double UnitsPerCentimetre(const Skeleton& skeleton) {
  constexpr double kCentimetreSpan = 10;  // see the header: no human-sized rig spans 10 m, or under 10 cm
  if (skeleton.units_per_centimetre > 0) return skeleton.units_per_centimetre;
  const bool bvh = std::any_of(skeleton.channels.begin(), skeleton.channels.end(),
                               [](const std::vector<Channel>& c) { return !c.empty(); });
  if (!bvh) return 0.01;  // glTF: metres
  const size_t n = skeleton.size();
  std::vector<Eigen::Vector3d> position(n);
  std::vector<Eigen::Matrix3d> linear(n);
  Eigen::Vector3d lo = Eigen::Vector3d::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  auto extend = [&](const Eigen::Vector3d& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  };
  for (size_t i = 0; i < n; ++i) {
    const Trs& rest = skeleton.rest[i];
    const Eigen::Matrix3d local = rest.rotation.normalized().toRotationMatrix() * rest.scale.asDiagonal();
    const int parent = skeleton.parents[i];
    if (parent < 0) {
      position[i] = rest.translation;
      linear[i] = local;
    } else {
      position[i] = position[parent] + linear[parent] * rest.translation;
      linear[i] = linear[parent] * local;
    }
    extend(position[i]);
    if (i < skeleton.end_sites.size() && skeleton.end_sites[i])
      extend(position[i] + linear[i] * *skeleton.end_sites[i]);
  }
  if (n == 0) return 1;
  return (hi - lo).maxCoeff() >= kCentimetreSpan ? 1.0 : 0.01;
}

Status CheckClipPrecision(const ClipPrecision& precision) {
  if (precision.exact) return Status::Ok();
  const double cm = precision.centimetres;
  if (!(cm > 0) || !(cm <= ClipPrecision::kMaxCentimetres))
    return Status::InvalidArgument("precision: " + std::to_string(cm) +
                                   " cm is not a bound; give one in (0, 10] centimetres, or 'exact'");
  return Status::Ok();
}

StatusOr<ClipPrecision> ParseClipPrecision(std::string_view text, std::string_view field,
                                           const ClipPrecision& fallback) {
  if (text.empty()) return fallback;
  ClipPrecision precision;
  if (text == "exact") {
    precision.exact = true;
    return precision;
  }
  const std::string owned(text);
  char* end = nullptr;
  precision.centimetres = std::strtod(owned.c_str(), &end);
  if (end == owned.c_str() || *end != '\0')
    return Status::InvalidArgument(std::string(field) + ": '" + owned +
                                   "' is not a bound; give one in (0, 10] centimetres, or 'exact'");
  if (Status checked = CheckClipPrecision(precision); !checked.ok())
    return Status::InvalidArgument(std::string(field) + ": '" + owned +
                                   "' is not a bound; give one in (0, 10] centimetres, or 'exact'");
  return precision;
}

std::string ClipPrecisionText(const ClipPrecision& precision) {
  if (precision.exact) return "exact";
  char text[32];
  for (int digits = 1; digits <= 17; ++digits) {
    std::snprintf(text, sizeof(text), "%.*g", digits, precision.centimetres);
    if (std::strtod(text, nullptr) == precision.centimetres) break;
  }
  return text;
}

StatusOr<ErrorBound> ResolveErrorBound(const Skeleton& skeleton, const ClipPrecision& precision) {
  ARMATURE_RETURN_IF_ERROR(CheckClipPrecision(precision));
  const double units = UnitsPerCentimetre(skeleton);
  ErrorBound bound;
  bound.precision = precision.exact ? 0 : precision.centimetres * units;
  bound.shell_distance = ClipPrecision::kShellCentimetres * units;
  return bound;
}

}  // namespace armature
