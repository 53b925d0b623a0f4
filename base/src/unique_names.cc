#include "armature/base/unique_names.h"

#include <utility>

namespace armature {

std::string UniqueNames::Take(std::string base) {
  if (taken_.insert(base).second) return base;
  unsigned long long& suffix = last_suffix_[base];
  std::string name;
  do {
    name = base;
    name += '_';  // not base + "_" + …: GCC 12's false -Wrestrict on that operator+
    name += std::to_string(++suffix);
  } while (!taken_.insert(name).second);
  return name;
}

}  // namespace armature
