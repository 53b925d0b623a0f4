#include "server/deform/deform_convert.h"

#include "server/deform/deform_validation.h"
#include "server/rpc/request_validation.h"

namespace armature::server {

v1::DeformSetup SetupOf(const v1::DeformRequest& request) {
  v1::DeformSetup s;
  s.set_mesh(request.mesh());
  s.set_weights(request.weights());
  s.set_method(request.method());
  *s.mutable_fixed() = request.fixed();
  *s.mutable_region_of_interest() = request.region_of_interest();
  s.set_soft(request.soft());
  s.set_soft_weight(request.soft_weight());
  s.set_arap_iterations(request.arap_iterations());
  return s;
}

Status SplitHandles(const v1::DeformRequest& request, std::vector<uint32_t>* indices, std::vector<double>* positions) {
  indices->clear();
  positions->clear();
  ARMATURE_RETURN_IF_ERROR(ValidateDeformHandles(request.handles()));
  for (const v1::DeformHandle& h : request.handles()) {
    indices->push_back(h.index());
    positions->insert(positions->end(), h.position().begin(), h.position().end());
  }
  return Status::Ok();
}

}  // namespace armature::server
