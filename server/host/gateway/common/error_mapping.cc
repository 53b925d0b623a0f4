#include "server/host/gateway/common/error_mapping.h"

#include <httplib.h>
#include <nlohmann/json.hpp>

namespace armature::server::gateway {

int HttpStatusOf(grpc::StatusCode code) {
  using G = grpc::StatusCode;
  switch (code) {
    case G::OK: return 200;
    case G::INVALID_ARGUMENT: return 400;
    case G::FAILED_PRECONDITION: return 400;  // as google.rpc.Code maps it: the client must change something first
    case G::UNAUTHENTICATED: return 401;
    case G::PERMISSION_DENIED: return 403;
    case G::NOT_FOUND: return 404;
    case G::ALREADY_EXISTS: return 409;
    case G::ABORTED: return 409;  // a lost read-modify-write race, as google.rpc.Code maps it
    case G::RESOURCE_EXHAUSTED: return 429;
    case G::CANCELLED: return 499;
    case G::UNIMPLEMENTED: return 501;
    case G::UNAVAILABLE: return 503;
    case G::DEADLINE_EXCEEDED: return 504;
    default: return 500;
  }
}

std::string ErrorJson(grpc::StatusCode code, const std::string& message) {
  // "replace" keeps a message with stray non-UTF-8 bytes printable.
  return nlohmann::ordered_json{
      {"code", static_cast<int>(code)}, {"message", message}, {"details", nlohmann::ordered_json::array()}}
      .dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);
}

void WriteError(httplib::Response& res, const grpc::Status& status) {
  WriteError(res, HttpStatusOf(status.error_code()), status.error_code(), status.error_message());
}

void WriteError(httplib::Response& res, int http_status, grpc::StatusCode code, const std::string& message) {
  res.status = http_status;
  res.set_content(ErrorJson(code, message) + "\n", "application/json");
}

}  // namespace armature::server::gateway
