// An OpenAPI 3.0 description of the REST API, generated from the same
// bindings and message descriptors the gateway serves: paths, methods,
// path and query parameters, request and response schemas (lowerCamelCase
// properties, enums as string enums).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "server/host/gateway/rest/transcoding/http_rule.h"

namespace armature::server::gateway {

struct OpenApiInfo {
  std::string title = "Armature REST API";
  std::string version = "v1";
  std::string description;
};

nlohmann::json OpenApiDocument(const std::vector<HttpBinding>& bindings, const OpenApiInfo& info);

}  // namespace armature::server::gateway
