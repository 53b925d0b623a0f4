// The REST routes: the (google.api.http) bindings of every served method,
// compiled once, and a request path matched against them. REST requests and
// WebSocket sessions (on their bidi method's REST path) are routed by it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <google/protobuf/descriptor.h>

#include "armature/base/status.h"
#include "server/host/gateway/rest/transcoding/http_rule.h"

namespace armature::server::gateway {

class RouteTable {
 public:
  struct Route {
    const HttpBinding* binding = nullptr;
    PathBindings variables;
  };

  // INVALID_ARGUMENT for a malformed rule or two methods claiming the same
  // HTTP method and path.
  static StatusOr<RouteTable> Compile(const std::vector<const google::protobuf::ServiceDescriptor*>& services);

  // The most specific binding of `http_method` that `path` matches.
  std::optional<Route> Match(const std::string& http_method, const RequestPath& path) const;
  std::string AllowedMethods(const RequestPath& path) const;  // "GET, DELETE" or ""
  const std::vector<HttpBinding>& bindings() const { return bindings_; }

 private:
  std::vector<Route> BestMatches(const RequestPath& path) const;

  std::vector<HttpBinding> bindings_;
};

}  // namespace armature::server::gateway
