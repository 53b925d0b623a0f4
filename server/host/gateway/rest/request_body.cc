#include "server/host/gateway/rest/request_body.h"

#include <algorithm>

#include <httplib.h>

#include "server/host/gateway/common/error_mapping.h"

namespace armature::server::gateway {

std::string TooLarge(size_t size, size_t limit, bool raw) {
  return "request body: " + std::to_string(size) + " bytes exceed the limit of " + std::to_string(limit) + " bytes (" +
         (raw ? "--max-upload-mb" : "--max-request-kb") + ")";
}

bool ReadBoundedBody(const httplib::Request& req, const httplib::ContentReader* reader, size_t limit, uint64_t declared,
                     bool raw, httplib::Response& res, std::string* body) {
  if (!reader) {
    *body = req.body;
    if (body->size() <= limit) return true;
    WriteError(res, 413, grpc::StatusCode::RESOURCE_EXHAUSTED, TooLarge(body->size(), limit, raw));
    return false;
  }
  size_t dropped = 0;
  const bool complete = (*reader)([&](const char* data, size_t n) {
    if (dropped == 0 && body->size() + n <= limit) {
      body->append(data, n);
      return true;
    }
    dropped += n;
    return dropped <= kDrainBytes;
  });
  if (dropped > 0 || res.status == 413) {
    if (!complete) res.set_header("Connection", "close");
    WriteError(res, 413, grpc::StatusCode::RESOURCE_EXHAUSTED,
               TooLarge(std::max<size_t>(declared, body->size() + dropped), limit, raw));
    return false;
  }
  if (!complete) {
    WriteError(res, 400, grpc::StatusCode::INVALID_ARGUMENT, "request body: could not be read (cut short?)");
    return false;
  }
  return true;
}

}  // namespace armature::server::gateway
