// A crowd session's bound motions (issue 31): each distinct Motion message
// (by its deterministic serialization) is looked up and bound once
// (BindMotionProto), and its characters share the plan, so the ticker keeps
// one layout and one blend workspace per motion.
#pragma once

#include <map>
#include <memory>
#include <string>

#include "armature/engine/anim/motion.h"
#include "armature/v1/motion.pb.h"
#include "server/assets/catalog.h"
#include "server/rpc/limits.h"

namespace armature::server {

class CrowdMotionPlans {
 public:
  explicit CrowdMotionPlans(const Limits& limits) : limits_(limits) {}

  // The bound plan of `motion`; errors name its field ("motion.layers[1]: …").
  StatusOr<std::shared_ptr<const MotionPlan>> PlanOf(const Catalog& catalog, const v1::Motion& motion);

 private:
  const Limits& limits_;
  std::map<std::string, std::shared_ptr<const MotionPlan>> plans_;
};

}  // namespace armature::server
