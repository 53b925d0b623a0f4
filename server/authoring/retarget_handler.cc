#include "server/authoring/retarget_handler.h"

#include <algorithm>
#include <string>
#include <vector>

#include "armature/engine/anim/body_part_map.h"
#include "armature/engine/kinematics/retarget/retarget.h"
#include "server/assets/asset_convert.h"
#include "server/authoring/derived_clip.h"

namespace armature::server {
namespace {

std::string DefaultName(const std::string& clip, const std::string& skeleton) {
  std::string name = clip + "_on_" + skeleton;
  std::replace(name.begin(), name.end(), '.', '_');
  return name;
}

}  // namespace

Status RetargetClip(AssetStore& store, const Limits& limits, const v1::RetargetClipRequest& request,
                    v1::RetargetClipResponse* response) {
  if (request.clip().empty()) return Status::InvalidArgument("clip is required (the source clip's name)");
  if (request.skeleton().empty()) return Status::InvalidArgument("skeleton is required (the target skeleton's name)");
  const std::shared_ptr<const Catalog> catalog = store.Snapshot();
  auto clip = catalog->FindClip(request.clip());
  if (!clip.ok()) return clip.status();
  auto skeleton = catalog->FindSkeleton(request.skeleton());
  if (!skeleton.ok()) return skeleton.status();
  const CompressedClip& source = *clip->part->runtime;
  const Skeleton& target = *skeleton->part->skeleton;

  std::vector<JointNamePair> explicit_pairs;
  explicit_pairs.reserve(static_cast<size_t>(request.map_size()));
  for (const v1::JointPair& p : request.map()) explicit_pairs.push_back({p.source(), p.target()});
  auto map = MapJointsByBodyParts(*source.skeleton, target, explicit_pairs);
  if (!map.ok()) return map.status();
  if (map->pairs.empty())
    return Status::InvalidArgument("no joint of clip '" + request.clip() + "' maps onto skeleton '" +
                                   request.skeleton() + "' by name; give the pairs in map (source=target)");

  RetargetOptions options;
  options.feet = request.feet();
  ARMATURE_ASSIGN_OR_RETURN(auto result, armature::RetargetClip(source, target, *map, options));

  DerivedClipOptions store_options;
  store_options.asset_name = request.name().empty() ? DefaultName(request.clip(), request.skeleton()) : request.name();
  store_options.skeleton = request.skeleton();
  store_options.replace = request.replace();
  ARMATURE_ASSIGN_OR_RETURN(auto stored, StoreDerivedClip(store, result.clip, store_options, limits));

  *response->mutable_clip() = ClipInfoOf(*stored.asset, *stored.clip, true);
  *response->mutable_asset() = AssetInfoOf(*stored.asset);
  for (const JointPairIndex& p : map->pairs) {
    v1::JointPair* pair = response->add_mapping();
    pair->set_source(source.skeleton->names[static_cast<size_t>(p.source)]);
    pair->set_target(target.names[static_cast<size_t>(p.target)]);
  }
  for (int j : map->unmapped_source)
    response->mutable_unmapped()->add_source(source.skeleton->names[static_cast<size_t>(j)]);
  for (int j : map->unmapped_target) response->mutable_unmapped()->add_target(target.names[static_cast<size_t>(j)]);
  for (std::string& w : result.warnings) response->add_warnings(std::move(w));
  return Status::Ok();
}

}  // namespace armature::server
