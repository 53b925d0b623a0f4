#include "server/crowd/crowd_motion_plans.h"

#include <utility>

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>

#include "server/assets/motion_convert.h"

namespace armature::server {
namespace {

std::string KeyOf(const v1::Motion& motion) {
  std::string key;
  google::protobuf::io::StringOutputStream stream(&key);
  google::protobuf::io::CodedOutputStream coded(&stream);
  coded.SetSerializationDeterministic(true);
  motion.SerializeToCodedStream(&coded);
  coded.Trim();
  return key;
}

}  // namespace

StatusOr<std::shared_ptr<const MotionPlan>> CrowdMotionPlans::PlanOf(const Catalog& catalog, const v1::Motion& motion) {
  std::string key = KeyOf(motion);
  if (auto it = plans_.find(key); it != plans_.end()) return it->second;
  ARMATURE_ASSIGN_OR_RETURN(MotionPlan plan, BindMotionProto(catalog, motion, limits_, "motion"));
  auto shared = std::make_shared<const MotionPlan>(std::move(plan));
  plans_.emplace(std::move(key), shared);
  return shared;
}

}  // namespace armature::server
