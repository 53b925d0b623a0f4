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

// The skeleton the poses are on: `skeleton`, `character`'s, or `own` (the clip's or motion's).
StatusOr<std::string> SkeletonNameOf(const Catalog& catalog, const v1::CrowdCharacter& m, const std::string& own) {
  if (!m.skeleton().empty() && !m.character().empty())
    return Status::InvalidArgument("skeleton and character: give one, not both");
  if (!m.character().empty()) {
    ARMATURE_RETURN_IF_ERROR(catalog.FindSkeleton(m.character()).status().WithContext("character: "));
    if (catalog.MeshesOf(m.character()).empty())
      return Status::NotFound("character: '" + m.character() + "' has no meshes skinned to it (not a character)");
    return m.character();
  }
  return m.skeleton().empty() ? own : m.skeleton();
}

// The skeleton the poses are on, whose joints must be `source`'s (same names, same order).
StatusOr<std::string> FittingSkeleton(const Catalog& catalog, const v1::CrowdCharacter& m, const std::string& own,
                                      const Skeleton& source, const std::string& what) {
  ARMATURE_ASSIGN_OR_RETURN(std::string name, SkeletonNameOf(catalog, m, own));
  auto skeleton = catalog.FindSkeleton(name);
  if (!skeleton.ok()) return skeleton.status().WithContext("skeleton: ");
  const Skeleton& target = *skeleton->part->skeleton;
  if (source.names != target.names)
    return Status::InvalidArgument(what + " animates " + std::to_string(source.size()) +
                                   " joints that are not skeleton '" + name + "''s " + std::to_string(target.size()) +
                                   " (same names in the same order)");
  return name;
}

// "motion:" and the layers' clips joined by "+".
std::string MotionName(const v1::Motion& motion) {
  std::string name = "motion:";
  for (int i = 0; i < motion.layers_size(); ++i) name += (i ? "+" : "") + motion.layers(i).clip();
  return name;
}

StatusOr<ResolvedCharacter> ResolveMotion(const Catalog& catalog, const v1::CrowdCharacter& m,
                                          CrowdMotionPlans& motions) {
  ARMATURE_ASSIGN_OR_RETURN(std::shared_ptr<const MotionPlan> plan, motions.PlanOf(catalog, m.motion()));
  // Bound, so layer 0's clip exists: its skeleton is the motion's.
  ARMATURE_ASSIGN_OR_RETURN(auto first, catalog.FindClip(m.motion().layers(0).clip()));
  ResolvedCharacter resolved;
  ARMATURE_ASSIGN_OR_RETURN(resolved.skeleton_name,
                            FittingSkeleton(catalog, m, first.part->skeleton_name, *plan->skeleton, "motion"));
  resolved.clip_name = MotionName(m.motion());
  resolved.motion = std::move(plan);
  return resolved;
}

StatusOr<ResolvedCharacter> ResolveClip(const Catalog& catalog, const v1::CrowdCharacter& m) {
  if (m.clip().empty()) return Status::InvalidArgument("clip or motion: required");
  auto clip = catalog.FindClip(m.clip());
  if (!clip.ok()) return clip.status().WithContext("clip: ");
  std::shared_ptr<const CompressedClip> runtime = clip->part->runtime;
  if (runtime == nullptr) return Status::Internal("clip: '" + m.clip() + "' has no runtime form");
  ResolvedCharacter resolved;
  ARMATURE_ASSIGN_OR_RETURN(resolved.skeleton_name, FittingSkeleton(catalog, m, clip->part->skeleton_name,
                                                                    *runtime->skeleton, "clip: '" + m.clip() + "'"));
  resolved.clip_name = m.clip();
  resolved.clip = std::move(runtime);
  return resolved;
}

}  // namespace

StatusOr<ResolvedCharacter> ResolveCharacter(const Catalog& catalog, const v1::CrowdCharacter& m,
                                             CrowdMotionPlans& motions) {
  const std::string who = "character " + std::to_string(m.id()) + ": ";
  if (Status st = CheckNumbers(m); !st.ok()) return st.WithContext(who);
  if (!m.clip().empty() && m.has_motion()) return Status::InvalidArgument(who + "clip and motion: give one, not both");
  auto resolved = m.has_motion() ? ResolveMotion(catalog, m, motions) : ResolveClip(catalog, m);
  if (!resolved.ok()) return resolved.status().WithContext(who);
  resolved->numbers = {.id = m.id(),
                       .time_offset = m.time_offset(),
                       .speed = m.speed() == 0 ? 1.0 : m.speed(),
                       .significance = m.significance()};
  return resolved;
}

}  // namespace armature::server
