// "Did you mean …?" for a name that is not there: the closest candidate by edit distance.
#pragma once

#include <string>
#include <string_view>
#include <vector>

namespace armature {

// The candidate closest to `name` (Levenshtein distance, case ignored) when it is close enough to be
// a typo: at most 2 edits, or a third of the name's length for longer names. "" when none is. A
// candidate's name without its namespace ("LeftHand" of "mixamorig:LeftHand") counts as well.
std::string ClosestName(std::string_view name, const std::vector<std::string_view>& candidates);

// "; did you mean 'X'?" when ClosestName finds one, else "".
std::string DidYouMean(std::string_view name, const std::vector<std::string_view>& candidates);

// "a, b, c" with at most `max_shown` names, then ", … (N more)".
std::string JoinNames(const std::vector<std::string_view>& names, size_t max_shown = 40);

// "unknown joint 'LeftWirst'; did you mean 'LeftWrist'? (the skeleton's 19 joints: Hips, …)", with
// `joints` the skeleton's joint names.
std::string UnknownJoint(std::string_view name, const std::vector<std::string>& joints);

}  // namespace armature
