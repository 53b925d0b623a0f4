// DeformService's unary work without gRPC (benchmarks, tests): one Deform
// solved on a deformer the cache shares between calls of the same setup.
#pragma once

#include <memory>

#include "armature/base/status.h"
#include "armature/v1/deform.pb.h"
#include "server/assets/catalog.h"
#include "server/deform/deformer_cache.h"
#include "server/rpc/limits.h"

namespace armature::server {

Status Deform(DeformerCache& cache, const std::shared_ptr<const Catalog>& catalog, const Limits& limits,
              const v1::DeformRequest& request, v1::DeformResponse* response);

}  // namespace armature::server
