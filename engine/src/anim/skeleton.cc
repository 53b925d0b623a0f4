#include "armature/engine/anim/skeleton.h"

#include <unordered_set>

namespace armature {

bool IsRotationChannel(Channel c) { return c >= Channel::kXrotation; }

std::string_view ChannelName(Channel c) {
  switch (c) {
    case Channel::kXposition: return "Xposition";
    case Channel::kYposition: return "Yposition";
    case Channel::kZposition: return "Zposition";
    case Channel::kXrotation: return "Xrotation";
    case Channel::kYrotation: return "Yrotation";
    case Channel::kZrotation: return "Zrotation";
  }
  return "?";
}

int Skeleton::Find(std::string_view name) const {
  for (size_t i = 0; i < names.size(); ++i)
    if (names[i] == name) return static_cast<int>(i);
  return -1;
}

Status Skeleton::Validate() const {
  const size_t n = names.size();
  if (n == 0) return Status::InvalidArgument("skeleton has no joints");
  if (parents.size() != n || rest.size() != n || channels.size() != n || end_sites.size() != n)
    return Status::InvalidArgument("skeleton arrays disagree in size");
  std::unordered_set<std::string_view> seen;
  for (size_t i = 0; i < n; ++i) {
    if (names[i].empty()) return Status::InvalidArgument("joint " + std::to_string(i) + " has no name");
    if (!seen.insert(names[i]).second) return Status::InvalidArgument("duplicate joint name '" + names[i] + "'");
    if (parents[i] < -1 || parents[i] >= static_cast<int>(i))
      return Status::InvalidArgument("joint '" + names[i] + "': parent must come before the joint");
    const Trs& r = rest[i];
    if (!r.translation.allFinite() || !r.rotation.coeffs().allFinite() || !r.scale.allFinite())
      return Status::InvalidArgument("joint '" + names[i] + "': rest transform is not finite");
    if (end_sites[i] && !end_sites[i]->allFinite())
      return Status::InvalidArgument("joint '" + names[i] + "': end site is not finite");
  }
  return Status::Ok();
}

}  // namespace armature
