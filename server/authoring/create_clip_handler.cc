#include "server/authoring/create_clip_handler.h"

#include <algorithm>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "armature/engine/anim/compression/clip_keys.h"
#include "armature/engine/anim/compression/error_bound.h"
#include "armature/engine/anim/cubic_tangents.h"
#include "server/assets/asset_convert.h"
#include "server/authoring/clip_bake.h"
#include "server/authoring/create_clip_validation.h"
#include "server/authoring/derived_clip.h"
#include "server/rpc/request_validation.h"

namespace armature::server {
namespace {

// With merge: the clip stored under `name`, which CreateClip named `name` in
// an asset the server made (record.animates), or "<name>.<name>" before clips
// were made their skeleton's own. An imported file's clip is never edited in
// place: a BVH "walk" holds a clip "walk" too.
StatusOr<PartRef<NamedClip>> StoredClipToEdit(const Catalog& catalog, const std::string& name) {
  auto asset = catalog.assets.find(name);
  if (asset == catalog.assets.end())
    return Status::NotFound("merge: there is no asset '" + name + "' to edit (create it first, without merge)");
  const bool server_made = !asset->second->record.animates.empty();
  for (const std::string& clip_name : {name, name + "." + name}) {
    if (clip_name == name && !server_made) continue;
    auto clip = catalog.clips.find(clip_name);
    if (clip != catalog.clips.end() && clip->second.asset == asset->second) return clip->second;
  }
  return Status::NotFound("merge: asset '" + name + "' has no clip '" + name +
                          "' (only clips made by CreateClip can be merged into)");
}

// The stored clip's tracks moved onto `skeleton` by joint name.
Status CarryOver(const Clip& stored, const Skeleton& skeleton, const std::string& skeleton_name, Clip& clip) {
  const Skeleton& from = *stored.skeleton;
  for (size_t j = 0; j < stored.joints.size(); ++j) {
    const JointTrack& t = stored.joints[j];
    if (t.translation.empty() && t.rotation.empty() && t.scale.empty()) continue;
    const int to = skeleton.Find(from.names[j]);
    if (to < 0)
      return Status::InvalidArgument("merge: the stored clip animates joint '" + from.names[j] + "', which skeleton '" +
                                     skeleton_name + "' does not have");
    clip.joints[static_cast<size_t>(to)] = t;
  }
  return Status::Ok();
}

// CUBIC tracks without tangents get the ones the cubic rules imply, so the
// stored glTF CUBICSPLINE curve is C¹ through the keys.
void CompleteCubicTangents(JointTrack& t) {
  auto needs = [](const auto& track) {
    return !track.empty() && track.interpolation == Interpolation::kCubic && track.in_tangents.empty();
  };
  if (needs(t.translation)) FillCubicTangents(t.translation);
  if (needs(t.rotation)) FillCubicTangents(t.rotation);
  if (needs(t.scale)) FillCubicTangents(t.scale);
}

// One try: reads the catalog, makes the clip, stores it (a merge only over
// the very asset it read, else ABORTED).
Status CreateClipOnce(AssetStore& store, const Limits& limits, const v1::CreateClipRequest& request,
                      v1::CreateClipResponse* response) {
  ARMATURE_RETURN_IF_ERROR(ValidateRequired(request.name(), "name"));
  ARMATURE_RETURN_IF_ERROR(ValidateAssetName(request.name()));
  ARMATURE_RETURN_IF_ERROR(ParseClipPrecision(request.precision(), "precision").status());
  const std::shared_ptr<const Catalog> catalog = store.Snapshot();
  if (request.has_bake() && request.merge())
    return Status::InvalidArgument("bake: not with merge (bake makes every joint's track anew)");

  std::optional<PartRef<NamedClip>> stored;
  if (request.merge()) {
    ARMATURE_ASSIGN_OR_RETURN(auto found, StoredClipToEdit(*catalog, request.name()));
    stored = found;
  }
  std::optional<BakedClip> baked;
  if (request.has_bake()) {
    ARMATURE_ASSIGN_OR_RETURN(auto made, BakeMotion(*catalog, limits, request.bake()));
    if (!request.skeleton().empty() && request.skeleton() != made.skeleton)
      return Status::InvalidArgument("skeleton: '" + request.skeleton() + "', but bake.motion animates skeleton '" +
                                     made.skeleton + "' (leave skeleton out or name that one)");
    baked = std::move(made);
  }
  std::shared_ptr<const Skeleton> skeleton;
  std::string skeleton_name = request.skeleton();
  if (baked) {
    skeleton = baked->clip.skeleton;
    skeleton_name = baked->skeleton;
  } else if (!skeleton_name.empty()) {
    ARMATURE_ASSIGN_OR_RETURN(auto found, catalog->FindSkeleton(skeleton_name));
    skeleton = found.part->skeleton;
  } else if (stored) {
    skeleton = stored->part->runtime->skeleton;
    skeleton_name = stored->part->skeleton_name;
  } else {
    return Status::InvalidArgument("skeleton: required (the skeleton the clip animates)");
  }

  ARMATURE_ASSIGN_OR_RETURN(auto keyed, KeyedJointsFromRequest(request, *skeleton, skeleton_name, limits));

  Clip clip;
  clip.skeleton = skeleton;
  clip.joints.resize(skeleton->size());
  if (baked) clip.joints = std::move(baked->clip.joints);
  if (stored) {
    ARMATURE_ASSIGN_OR_RETURN(const std::shared_ptr<const Clip> keys, ClipKeysOf(*stored->part->runtime));
    ARMATURE_RETURN_IF_ERROR(CarryOver(*keys, *skeleton, skeleton_name, clip));
  }
  for (KeyedJoint& k : keyed) {
    JointTrack& t = clip.joints[static_cast<size_t>(k.joint)];
    t = k.remove ? JointTrack{} : std::move(k.track);
  }
  for (JointTrack& t : clip.joints) {
    CompleteCubicTangents(t);
    for (const std::vector<double>* times : {&t.translation.times, &t.rotation.times, &t.scale.times}) {
      if (times->empty()) continue;
      clip.duration = std::max(clip.duration, times->back());
      clip.frame_count = std::max(clip.frame_count, times->size());
    }
  }
  if (clip.frame_count == 0)
    return Status::InvalidArgument("tracks: the clip would have no keys (give at least one track with times)");
  ARMATURE_RETURN_IF_ERROR(clip.Validate());

  DerivedClipOptions options;
  options.asset_name = request.name();
  // A merge into an older clip that animates its own asset's copy of a skeleton keeps it so.
  const bool own_copy = stored && stored->asset->record.animates.empty();
  options.skeleton = own_copy ? "" : skeleton_name;
  options.replace = request.replace() || request.merge();
  if (stored) options.replace_only = stored->asset;
  // Authored keys stay as given, tangents too, so a later merge carries them
  // over as they are; a bake is motion the server made, held like an import.
  options.precision = !request.precision().empty() ? request.precision() : request.has_bake() ? "" : "exact";
  ARMATURE_ASSIGN_OR_RETURN(auto derived, StoreDerivedClip(store, clip, options, limits));
  *response->mutable_clip() = ClipInfoOf(*derived.asset, *derived.clip, true);
  *response->mutable_asset() = AssetInfoOf(*derived.asset);
  for (const std::string& w : derived.asset->contents.warnings) response->add_warnings(w);  // e.g. "kept exact"
  return Status::Ok();
}

}  // namespace

Status CreateClip(AssetStore& store, const Limits& limits, const v1::CreateClipRequest& request,
                  v1::CreateClipResponse* response) {
  // A merge reads the stored clip and writes it back. When another write to
  // that asset lands in between, the store refuses (ABORTED) rather than lose
  // it, and the merge is made again from the newer clip.
  constexpr int kMergeAttempts = 16;
  for (int attempt = 1;; ++attempt) {
    Status status = CreateClipOnce(store, limits, request, response);
    if (status.code() != StatusCode::kAborted || attempt == kMergeAttempts) return status;
  }
}

}  // namespace armature::server
