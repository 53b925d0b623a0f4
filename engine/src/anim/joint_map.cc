#include "armature/engine/anim/joint_map.h"

#include <cmath>
#include <string>

namespace armature {
namespace {

constexpr size_t kNamedMissing = 5;  // joints a mismatch names before "and N more"

}  // namespace

Status MapJointsByName(const Skeleton& target, const Skeleton& source, std::string_view target_label,
                       std::vector<int>& out) {
  out.resize(target.size());
  if (&target == &source) {
    for (size_t j = 0; j < out.size(); ++j) out[j] = static_cast<int>(j);
    return Status::Ok();
  }
  size_t missing = 0;
  std::string named;
  for (size_t j = 0; j < target.size(); ++j) {
    out[j] = source.Find(target.names[j]);
    if (out[j] >= 0) continue;
    if (missing++ < kNamedMissing) named += (named.empty() ? "'" : ", '") + target.names[j] + "'";
  }
  if (missing == 0) return Status::Ok();
  if (missing > kNamedMissing) named += " and " + std::to_string(missing - kNamedMissing) + " more";
  return Status::InvalidArgument("lacks " + std::to_string(missing) + " of the " + std::to_string(target.size()) +
                                 " joints of " + std::string(target_label) + ": " + named);
}

}  // namespace armature
