#include "server/rpc/call_guard.h"

#include <new>

#include <spdlog/spdlog.h>

#include "armature/base/utf8.h"

namespace armature::server {

std::string RequestIdOf(const grpc::ServerContextBase& context) {
  const auto& metadata = context.client_metadata();
  const auto it = metadata.find("x-request-id");
  if (it == metadata.end() || it->second.empty() || it->second.size() > 128) return "-";
  std::string id(it->second.data(), it->second.size());
  for (char c : id)
    if (c < 0x21 || c > 0x7e) return "-";
  return id;
}

Status StatusOfCurrentException(const grpc::ServerContextBase* context, std::string_view where) noexcept {
  try {
    const std::string id = context ? RequestIdOf(*context) : "-";
    try {
      throw;
    } catch (const std::bad_alloc&) {
      spdlog::error("{}: out of memory serving request {}", where, id);
      return Status::ResourceExhausted(std::string(where) +
                                       ": the server ran out of memory serving this request; try a smaller one");
    } catch (const std::exception& e) {
      const std::string what = EscapeForMessage(e.what(), 1024);
      spdlog::error("{}: internal error serving request {}: {}", where, id, what);
      return Status(StatusCode::kInternal, std::string(where) + ": internal error: " + what);
    } catch (...) {
      spdlog::error("{}: internal error serving request {}: unknown exception", where, id);
      return Status(StatusCode::kInternal, std::string(where) + ": internal error");
    }
  } catch (...) {  // the log or the message could not be allocated
    return Status(StatusCode::kResourceExhausted, "out of memory");
  }
}

}  // namespace armature::server
