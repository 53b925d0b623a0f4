#include "server/host/gateway/rest/route_table.h"

#include <map>
#include <set>

namespace armature::server::gateway {

StatusOr<RouteTable> RouteTable::Compile(const std::vector<const google::protobuf::ServiceDescriptor*>& services) {
  RouteTable table;
  std::map<std::string, std::string> claimed;  // "GET /v1/x/{}" → method
  for (const auto* service : services) {
    for (int i = 0; i < service->method_count(); ++i) {
      ARMATURE_ASSIGN_OR_RETURN(std::vector<HttpBinding> bindings, BindingsOf(service->method(i)));
      for (auto& b : bindings) {
        const std::string key = b.http_method + " " + b.path.Simplified();
        if (auto [it, fresh] = claimed.emplace(key, b.method->full_name()); !fresh)
          return Status::InvalidArgument("(google.api.http): " + key + " is bound to both " + it->second + " and " +
                                         b.method->full_name());
        table.bindings_.push_back(std::move(b));
      }
    }
  }
  return table;
}

// A path can match several templates: "/v1/clips/a:evaluate" matches
// "/v1/clips/{clip}:evaluate" and, as a clip named "a:evaluate",
// "/v1/clips/{clip}". Only the most specific ones count, whatever their method.
std::vector<RouteTable::Route> RouteTable::BestMatches(const RequestPath& path) const {
  std::vector<Route> best;
  PathBindings variables;
  for (const HttpBinding& b : bindings_) {
    if (!b.path.Match(path, &variables)) continue;
    if (!best.empty() && b.path.specificity() < best.front().binding->path.specificity()) continue;
    if (!best.empty() && b.path.specificity() > best.front().binding->path.specificity()) best.clear();
    best.push_back(Route{&b, variables});
  }
  return best;
}

std::optional<RouteTable::Route> RouteTable::Match(const std::string& http_method, const RequestPath& path) const {
  for (auto& route : BestMatches(path))
    if (route.binding->http_method == http_method) return std::move(route);
  return std::nullopt;
}

std::string RouteTable::AllowedMethods(const RequestPath& path) const {
  std::set<std::string> methods;
  for (const auto& route : BestMatches(path)) methods.insert(route.binding->http_method);
  if (methods.count("GET")) methods.insert("HEAD");
  std::string out;
  for (const auto& m : methods) out += (out.empty() ? "" : ", ") + m;
  return out;
}

}  // namespace armature::server::gateway
