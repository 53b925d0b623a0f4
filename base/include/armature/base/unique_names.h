// Names made unique within one file's import: a name already taken gets
// "_1", "_2", … (the first free one).
#pragma once

#include <map>
#include <set>
#include <string>

namespace armature {

// Each base name remembers the last suffix it took, so n copies of one
// name cost about n set lookups, not n²/2: an importer asked for the next
// free suffix from 1 each time took 20 s on a 1.2 MB FBX of 16,000 nodes
// named alike (a fuzzer's find).
class UniqueNames {
 public:
  // `base` when free, else base + "_" + the lowest number not taken yet
  // after this base's last one; the name returned is taken.
  std::string Take(std::string base);

 private:
  std::set<std::string> taken_;
  std::map<std::string, unsigned long long> last_suffix_;
};

}  // namespace armature
