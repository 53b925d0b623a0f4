#include "server/assets/part_deletion.h"

#include <string>
#include <vector>

namespace armature::server {
namespace {

template <class Part>
size_t CountOthers(const std::vector<Part>& parts, std::string_view name, const char*& kind, const char* this_kind) {
  size_t others = 0;
  for (const Part& p : parts) {
    if (p.name == name)
      kind = this_kind;
    else
      ++others;
  }
  return others;
}

std::string Counted(size_t n, const char* singular, const char* plural) {
  return std::to_string(n) + " " + (n == 1 ? singular : plural);
}

}  // namespace

Status CheckDeletionTakesOnly(const StoredAsset& owner, std::string_view name) {
  const AssetRecord& record = owner.record;
  if (name == record.name) return Status::Ok();
  const AssetContents& c = owner.contents;
  const char* kind = "part";
  const size_t clips = CountOthers(c.clips, name, kind, "clip");
  const size_t meshes = CountOthers(c.meshes, name, kind, "mesh");
  const size_t skeletons = CountOthers(c.skeletons, name, kind, "skeleton");
  std::vector<std::string> held;
  if (clips) held.push_back(Counted(clips, "clip", "clips"));
  if (meshes) held.push_back(Counted(meshes, "mesh", "meshes"));
  if (skeletons) held.push_back(Counted(skeletons, "skeleton", "skeletons"));
  if (held.empty()) return Status::Ok();
  std::string list = held[0];
  for (size_t i = 1; i < held.size(); ++i) list += (i + 1 == held.size() ? " and " : ", ") + held[i];
  return Status::FailedPrecondition(std::string(kind) + " '" + std::string(name) + "' belongs to asset '" +
                                    record.name + "', which also holds " + list + "; delete the asset '" + record.name +
                                    "' to remove them all");
}

}  // namespace armature::server
