// IK messages ↔ engine IkRequest / IkResult. Errors name the API field
// ("effectors[1].target_position", "start_pose.rotations", "limits[0].order").
#pragma once

#include <string>
#include <vector>

#include <google/protobuf/repeated_field.h>

#include "armature/engine/kinematics/ik_body_root.h"
#include "armature/engine/kinematics/ik_types.h"
#include "armature/base/status.h"
#include "armature/v1/ik.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"
#include "server/rpc/convert/pose_convert.h"

namespace armature::server {

// A SolveIkRequest resolved against the catalog: the skeleton (held for the
// call's life), the engine request and the start pose its span views.
struct IkCall {
  PartRef<NamedSkeleton> skeleton;
  IkRequest request;
  std::vector<Trs> start;                     // empty = the rest pose
  std::vector<uint8_t> body_root_candidates;  // request.body_root_candidates views it
};

// Fills `call` from `in`: looks up the skeleton and any from_clip, samples
// or converts the start pose, converts effectors, limits and options
// (options.max_iterations over limits.max_ik_iterations is
// RESOURCE_EXHAUSTED). The engine checks the rest when solving; pass its
// errors through ApiFieldNames.
Status IkCallFromProto(const Catalog& catalog, const Limits& limits, const v1::SolveIkRequest& in, IkCall& call);

// New targets of a session message applied to `request`'s effectors.
Status ApplyTargetUpdates(const google::protobuf::RepeatedPtrField<v1::IkTargetUpdate>& updates, IkRequest& request);

// The engine names the start pose "pose.…" (PoseFromArrays) and
// "start_pose[i]"; the API calls it start_pose. Its free_root_rotation and
// free_root_translation are the API's free_root.
Status ApiFieldNames(const Status& status);

// `result` as an answer: the pose in both spaces, every joint, residuals.
void IkResponseToProto(const IkCall& call, const IkResult& result, PoseWorkspace& ws, v1::SolveIkResponse* out);

}  // namespace armature::server
