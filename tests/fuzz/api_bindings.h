// The REST bindings of every Armature RPC, compiled once per fuzz process.
#pragma once

#include <cstdlib>
#include <vector>

#include "server/host/gateway/http_rule.h"

namespace armature::fuzz {

inline const std::vector<server::gateway::HttpBinding>& ApiBindings() {
  static const auto* bindings = [] {
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
