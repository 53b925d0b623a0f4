#include "server/crowd/crowd_character.h"

#include <string>

#include "server/rpc/request_validation.h"

namespace armature::server {
namespace {

Status CheckRoot(const v1::CrowdRoot& root) {
  if (root.translation_size() != 0 && root.translation_size() != 3)
    return Status::InvalidArgument("root.translation: 3 values or none, not " +
                                   std::to_string(root.translation_size()));
  if (root.rotation_size() != 0 && root.rotation_size() != 4)
    return Status::InvalidArgument("root.rotation: 4 values (w, x, y, z) or none, not " +
                                   std::to_string(root.rotation_size()));
  for (int i = 0; i < root.translation_size(); ++i)
    ARMATURE_RETURN_IF_ERROR(ValidateFinite(root.translation(i), "root.translation[" + std::to_string(i) + "]"));
  for (int i = 0; i < root.rotation_size(); ++i)
    ARMATURE_RETURN_IF_ERROR(ValidateFinite(root.rotation(i), "root.rotation[" + std::to_string(i) + "]"));
  return Status::Ok();
}

Status CheckNumbers(const v1::CrowdCharacter& m) {
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(m.time_offset(), "time_offset"));
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(m.speed(), "speed"));
  ARMATURE_RETURN_IF_ERROR(ValidateFinite(m.significance(), "significance"));
  return CheckRoot(m.root());
}

// The skeleton the poses are on: `skeleton`, `character`'s, or the clip's own.
StatusOr<std::string> SkeletonNameOf(const Catalog& catalog, const v1::CrowdCharacter& m, const NamedClip& clip) {
  if (!m.skeleton().empty() && !m.character().empty())
    return Status::InvalidArgument("skeleton and character: give one, not both");
  if (!m.character().empty()) {
    ARMATURE_RETURN_IF_ERROR(catalog.FindSkeleton(m.character()).status().WithContext("character: "));
    if (catalog.MeshesOf(m.character()).empty())
      return Status::NotFound("character: '" + m.character() + "' has no meshes skinned to it (not a character)");
    return m.character();
  }
  return m.skeleton().empty() ? clip.skeleton_name : m.skeleton();
}

}  // namespace

StatusOr<ResolvedCharacter> ResolveCharacter(const Catalog& catalog, const v1::CrowdCharacter& m) {
  const std::string who = "character " + std::to_string(m.id()) + ": ";
  if (Status st = CheckNumbers(m); !st.ok()) return st.WithContext(who);
  if (m.clip().empty()) return Status::InvalidArgument(who + "clip: required");
  auto clip = catalog.FindClip(m.clip());
  if (!clip.ok()) return clip.status().WithContext(who + "clip: ");
  auto skeleton_name = SkeletonNameOf(catalog, m, *clip->part);
  if (!skeleton_name.ok()) return skeleton_name.status().WithContext(who);
  auto skeleton = catalog.FindSkeleton(*skeleton_name);
  if (!skeleton.ok()) return skeleton.status().WithContext(who + "skeleton: ");
  const Skeleton& target = *skeleton->part->skeleton;
  std::shared_ptr<const CompressedClip> runtime = clip->part->runtime;
  if (runtime == nullptr) return Status::Internal(who + "clip: '" + m.clip() + "' has no runtime form");
  const Skeleton& source = *runtime->skeleton;
  if (source.names != target.names)
    return Status::InvalidArgument(who + "clip: '" + m.clip() + "' animates " + std::to_string(source.size()) +
                                   " joints that are not skeleton '" + *skeleton_name + "''s " +
                                   std::to_string(target.size()) + " (same names in the same order)");
  ResolvedCharacter resolved;
  resolved.clip_name = m.clip();
  resolved.skeleton_name = *skeleton_name;
  resolved.clip = std::move(runtime);
  resolved.numbers = {.id = m.id(),
                      .time_offset = m.time_offset(),
                      .speed = m.speed() == 0 ? 1.0 : m.speed(),
                      .significance = m.significance()};
  return resolved;
}

}  // namespace armature::server
