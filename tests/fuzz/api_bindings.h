// The REST bindings of every Armature RPC, compiled once per fuzz process.
#pragma once

#include <cstdlib>
#include <vector>

#include "armature/v1/assets.pb.h"
#include "armature/v1/deform.pb.h"
#include "armature/v1/ik.pb.h"
#include "armature/v1/meshes.pb.h"
#include "armature/v1/poses.pb.h"
#include "server/host/gateway/rest/transcoding/http_rule.h"

namespace armature::fuzz {

inline const std::vector<server::gateway::HttpBinding>& ApiBindings() {
  static const auto* bindings = [] {
    // The generated files register themselves only when linked in: name one
    // message of each file with services.
    for (const auto* d :
         {v1::ImportAssetRequest::descriptor(), v1::DeformRequest::descriptor(), v1::SolveIkRequest::descriptor(),
          v1::GetMeshRequest::descriptor(), v1::EvaluateClipRequest::descriptor()})
      if (d->file()->service_count() == 0) std::abort();
    auto* out = new std::vector<server::gateway::HttpBinding>();
    for (const auto* service : server::gateway::GeneratedServicesIn("armature"))
      for (int i = 0; i < service->method_count(); ++i) {
        auto b = server::gateway::BindingsOf(service->method(i));
        if (!b.ok()) std::abort();
        for (auto& binding : *b) out->push_back(std::move(binding));
      }
    if (out->empty()) std::abort();
    return out;
  }();
  return *bindings;
}

}  // namespace armature::fuzz
