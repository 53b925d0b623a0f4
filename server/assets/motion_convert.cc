#include "server/assets/motion_convert.h"

#include "server/rpc/request_validation.h"

namespace armature::server {
namespace {

LayerMode ModeOf(v1::MotionLayer::Mode mode) {
  return mode == v1::MotionLayer::ADDITIVE ? LayerMode::kAdditive : LayerMode::kOverride;
}

TimeSync SyncOf(v1::Motion::Sync sync) { return sync == v1::Motion::PHASE ? TimeSync::kPhase : TimeSync::kNone; }

RootMotion RootMotionOf(v1::Motion::RootMotion mode) {
  switch (mode) {
    case v1::Motion::IN_PLACE: return RootMotion::kInPlace;
    case v1::Motion::ACCUMULATE: return RootMotion::kAccumulate;
    case v1::Motion::EXTRACT: return RootMotion::kExtract;
    default: return RootMotion::kKeep;
  }
}

}  // namespace

StatusOr<Motion> MotionFromProto(const Catalog& catalog, const v1::Motion& motion, const Limits& limits,
                                 const std::string& field) {
  ARMATURE_RETURN_IF_ERROR(ValidateMotion(motion, limits, field));
  Motion out;
  out.sync = SyncOf(motion.sync());
  out.root_motion = RootMotionOf(motion.root_motion());
  out.root_joint = motion.root_joint();
  out.layers.reserve(motion.layers_size());
  for (int i = 0; i < motion.layers_size(); ++i) {
    const v1::MotionLayer& l = motion.layers(i);
    auto ref = catalog.FindClip(l.clip());
    if (!ref.ok()) return ref.status().WithContext(field + ".layers[" + std::to_string(i) + "]: ");
    MotionLayer layer;
    layer.clip = ref->part->runtime;
    layer.clip_name = l.clip();
    layer.weight = l.has_weight() ? l.weight() : 1.0;
    layer.speed = l.has_speed() ? l.speed() : 1.0;
    layer.time_offset = l.time_offset();
    layer.mode = ModeOf(l.mode());
    layer.reference_time = l.reference_time();
    layer.wrap = l.wrap() == v1::CLAMP ? WrapMode::kClamp : WrapMode::kLoop;  // layers loop unless told
    for (int k = 0; k < l.mask_size(); ++k)
      layer.mask.push_back({l.mask(k), l.mask_weights().empty() ? 1.0 : l.mask_weights(k)});
    out.layers.push_back(std::move(layer));
  }
  return out;
}

StatusOr<MotionPlan> BindMotionProto(const Catalog& catalog, const v1::Motion& motion, const Limits& limits,
                                     const std::string& field) {
  ARMATURE_ASSIGN_OR_RETURN(auto m, MotionFromProto(catalog, motion, limits, field));
  auto plan = BindMotion(m);
  if (!plan.ok()) return plan.status().WithContext(field + ".");
  return plan;
}

}  // namespace armature::server
