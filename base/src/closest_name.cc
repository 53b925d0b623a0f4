#include "armature/base/closest_name.h"

#include <algorithm>
#include <cctype>

namespace armature {
namespace {

// Names longer than this get no suggestion: the distance costs length², and no typo is that long.
constexpr size_t kMaxComparedLength = 128;

size_t EditDistance(std::string_view a, std::string_view b) {
  std::vector<size_t> row(b.size() + 1);
  for (size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (size_t i = 1; i <= a.size(); ++i) {
    size_t diagonal = row[0];
    row[0] = i;
    for (size_t j = 1; j <= b.size(); ++j) {
      const bool same =
          std::tolower(static_cast<unsigned char>(a[i - 1])) == std::tolower(static_cast<unsigned char>(b[j - 1]));
      const size_t next = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (same ? 0 : 1)});
      diagonal = row[j];
      row[j] = next;
    }
  }
  return row[b.size()];
}

// A name without its namespace: "mixamorig:LeftHand" → "LeftHand", "rig|Hips" → "Hips". Exporters
// prefix every joint, and a user types the part they see.
std::string_view WithoutNamespace(std::string_view name) {
  const size_t cut = name.find_last_of(":|");
  return cut == std::string_view::npos || cut + 1 == name.size() ? name : name.substr(cut + 1);
}

}  // namespace

std::string ClosestName(std::string_view name, const std::vector<std::string_view>& candidates) {
  if (name.empty() || name.size() > kMaxComparedLength) return "";
  const size_t allowed = std::max<size_t>(2, name.size() / 3);
  std::string_view best;
  size_t best_distance = allowed + 1;
  for (std::string_view c : candidates) {
    if (c.size() > kMaxComparedLength || c == name) continue;
    // The whole name, or the name without its namespace prefix, whichever is closer.
    for (std::string_view compared : {c, WithoutNamespace(c)}) {
      const size_t gap = compared.size() > name.size() ? compared.size() - name.size() : name.size() - compared.size();
      if (gap >= best_distance) continue;
      const size_t d = EditDistance(name, compared);
      if (d < best_distance && d < std::max(name.size(), compared.size())) best = c, best_distance = d;
    }
  }
  return std::string(best);
}

std::string DidYouMean(std::string_view name, const std::vector<std::string_view>& candidates) {
  const std::string closest = ClosestName(name, candidates);
  return closest.empty() ? "" : "; did you mean '" + closest + "'?";
}

std::string JoinNames(const std::vector<std::string_view>& names, size_t max_shown) {
  std::string out;
  for (size_t i = 0; i < names.size() && i < max_shown; ++i) {
    if (i) out += ", ";
    out += names[i];
  }
  if (names.size() > max_shown) out += ", … (" + std::to_string(names.size() - max_shown) + " more)";
  return out;
}

std::string UnknownJoint(std::string_view name, const std::vector<std::string>& joints) {
  const std::vector<std::string_view> views(joints.begin(), joints.end());
  return "unknown joint '" + std::string(name) + "'" + DidYouMean(name, views) + " (the skeleton's " +
         std::to_string(views.size()) + " joints: " + JoinNames(views) + ")";
}

}  // namespace armature
