// Motion messages → the engine's MotionPlan: clips looked up in the catalog,
// then validated and bound (joint maps, masks, root motion) by the engine.
#pragma once

#include <string>

#include "armature/engine/anim/motion.h"
#include "armature/v1/motion.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"

namespace armature::server {

// A motion as the engine describes it. Checks the message first
// (ValidateMotion); an unknown clip is NOT_FOUND naming the layer
// ("motion.layers[1]: clip 'Wave' not found"). `field` names the message in errors.
StatusOr<Motion> MotionFromProto(const Catalog& catalog, const v1::Motion& motion, const Limits& limits,
                                 const std::string& field);

// MotionFromProto, then BindMotion; errors carry `field` as a prefix.
StatusOr<MotionPlan> BindMotionProto(const Catalog& catalog, const v1::Motion& motion, const Limits& limits,
                                     const std::string& field);

}  // namespace armature::server
