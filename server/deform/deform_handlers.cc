#include "server/deform/deform_handlers.h"

#include <cstdint>
#include <vector>

#include "server/deform/deform_convert.h"
#include "server/deform/mesh_deformer.h"

namespace armature::server {

Status Deform(DeformerCache& cache, const std::shared_ptr<const Catalog>& catalog, const Limits& limits,
              const v1::DeformRequest& request, v1::DeformResponse* response) {
  std::vector<uint32_t> handles;
  std::vector<double> positions;
  ARMATURE_RETURN_IF_ERROR(SplitHandles(request, &handles, &positions));
  ARMATURE_ASSIGN_OR_RETURN(auto deformer, cache.Get(catalog, limits, SetupOf(request), std::move(handles)));
  return deformer->SolveFresh(positions, "handles", response);
}

}  // namespace armature::server
