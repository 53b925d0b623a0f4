// gRPC status → HTTP status and the JSON error body every gateway error has:
// {"code": <gRPC numeric code>, "message": "...", "details": []}.
#pragma once

#include <string>

#include <grpcpp/grpcpp.h>

namespace httplib {
struct Response;
}

namespace armature::server::gateway {

int HttpStatusOf(grpc::StatusCode code);

std::string ErrorJson(grpc::StatusCode code, const std::string& message);

// Writes the error with the HTTP status its code maps to.
void WriteError(httplib::Response& res, const grpc::Status& status);
// Writes the error with an explicit HTTP status (404, 405, 413: HTTP-level errors).
void WriteError(httplib::Response& res, int http_status, grpc::StatusCode code, const std::string& message);

}  // namespace armature::server::gateway
