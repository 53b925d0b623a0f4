// UniqueNames: a taken name gets the lowest free "_N" suffix, as importers
// name joints, meshes and clips that a file repeats.
#include <gtest/gtest.h>

#include <algorithm>
#include <string>
#include <vector>

#include "armature/base/unique_names.h"

namespace armature {
namespace {

TEST(UniqueNames, RepeatsTakeTheNextSuffix) {
  UniqueNames names;
  EXPECT_EQ(names.Take("Hips"), "Hips");
  EXPECT_EQ(names.Take("Hips"), "Hips_1");
  EXPECT_EQ(names.Take("Spine"), "Spine");
  EXPECT_EQ(names.Take("Hips"), "Hips_2");
  EXPECT_EQ(names.Take(""), "");
  EXPECT_EQ(names.Take(""), "_1");
}

TEST(UniqueNames, ASuffixAnotherNameTookIsSkipped) {
  UniqueNames names;
  EXPECT_EQ(names.Take("A"), "A");
  EXPECT_EQ(names.Take("A_2"), "A_2");
  EXPECT_EQ(names.Take("A"), "A_1");
  EXPECT_EQ(names.Take("A"), "A_3");  // A_2 was taken as a name of its own
  EXPECT_EQ(names.Take("A_1"), "A_1_1");
  EXPECT_EQ(names.Take("A"), "A_4");
}

// The lowest free suffix, as the importers' earlier search from 1 found it:
// names are never given back, so every suffix up to a base's last is taken.
TEST(UniqueNames, TheSameNamesAsASearchFromOne) {
  const std::vector<std::string> bases = {"a", "a_1", "a", "b", "a_3", "a", "a", "b_1", "b", "a_5_1", "a", "a"};
  UniqueNames names;
  std::vector<std::string> taken;
  for (const std::string& base : bases) {
    std::string expected = base;
    for (int i = 1; std::find(taken.begin(), taken.end(), expected) != taken.end(); ++i)
      expected = base + "_" + std::to_string(i);
    taken.push_back(expected);
    EXPECT_EQ(names.Take(base), expected) << "base '" << base << "'";
  }
}

}  // namespace
}  // namespace armature
