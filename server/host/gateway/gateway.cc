#include "server/host/gateway/gateway.h"

#include <httplib.h>
#include <spdlog/spdlog.h>

#include "armature/base/utf8.h"
#include "server/host/gateway/common/error_mapping.h"
#include "server/host/gateway/rest/openapi.h"
#include "server/host/gateway/websocket/websocket_handshake.h"

namespace armature::server::gateway {
namespace {

namespace pb = google::protobuf;
using httplib::Server;

// Removes "br" from every Accept-Encoding header (see RegisterPreRouting).
void DropBrotli(httplib::Headers& headers) {
  auto [begin, end] = headers.equal_range("Accept-Encoding");
  for (auto it = begin; it != end; ++it) {
    std::string kept;
    size_t start = 0;
    while (start <= it->second.size()) {
      size_t comma = it->second.find(',', start);
      if (comma == std::string::npos) comma = it->second.size();
      std::string token = it->second.substr(start, comma - start);
      const size_t first = token.find_first_not_of(" \t");
      const std::string coding =
          first == std::string::npos ? "" : token.substr(first, token.find_first_of(" \t;", first) - first);
      if (!coding.empty() && coding != "br") kept += (kept.empty() ? "" : ", ") + token.substr(first);
      start = comma + 1;
    }
    it->second = kept;
  }
}

// Errors cpp-httplib produces itself (bad request line, oversized URI) get the JSON shape too.
Server::HandlerResponse AnswerHttplibError(const httplib::Request&, httplib::Response& res) {
  if (!res.body.empty() || res.is_chunked_content_provider_) return Server::HandlerResponse::Unhandled;
  const grpc::StatusCode code = res.status == 404   ? grpc::StatusCode::NOT_FOUND
                                : res.status == 413 ? grpc::StatusCode::RESOURCE_EXHAUSTED
                                : res.status < 500  ? grpc::StatusCode::INVALID_ARGUMENT
                                                    : grpc::StatusCode::INTERNAL;
  const std::string what = res.status == 400   ? "bad request"
                           : res.status == 413 ? "request too large"
                           : res.status == 414 ? "request URI too long"
                                               : "HTTP error " + std::to_string(res.status);
  WriteError(res, res.status, code, what);
  return Server::HandlerResponse::Handled;
}

// The exception boundary of REST handlers (see server/rpc/call_guard.h for gRPC's).
void AnswerException(const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
  std::string what = "unknown exception";
  bool out_of_memory = false;
  try {
    std::rethrow_exception(ep);
  } catch (const std::bad_alloc&) {
    out_of_memory = true;
    what = "out of memory";
  } catch (const std::exception& e) {
    what = EscapeForMessage(e.what(), 1024);
  } catch (...) {}
  const std::string id = req.has_header("x-request-id") ? EscapeForMessage(req.get_header_value("x-request-id")) : "-";
  spdlog::error("gateway: {} {} (request {}): {}", req.method, EscapeForMessage(req.path, 256), id, what);
  if (out_of_memory)
    return WriteError(res, 503, grpc::StatusCode::RESOURCE_EXHAUSTED,
                      "the server ran out of memory serving this request; try a smaller one");
  WriteError(res, 500, grpc::StatusCode::INTERNAL, "internal error: " + what);
}

}  // namespace

Gateway::Gateway(RouteTable routes, const std::vector<const pb::ServiceDescriptor*>& services,
                 pb::MessageFactory* factory, std::shared_ptr<grpc::Channel> channel, GatewayOptions options)
    : calls_(std::move(options), factory, std::move(channel)),
      cors_(calls_.options().cors_origins),
      routes_(std::move(routes)),
      openapi_(OpenApiDocument(routes_.bindings(), {}).dump(2)),
      rest_(routes_, calls_),
      grpc_web_(services, calls_),
      websocket_(routes_, calls_) {}

StatusOr<std::unique_ptr<Gateway>> Gateway::Create(const std::vector<const pb::ServiceDescriptor*>& services,
                                                   pb::MessageFactory* factory, std::shared_ptr<grpc::Channel> channel,
                                                   GatewayOptions options) {
  ARMATURE_ASSIGN_OR_RETURN(RouteTable routes, RouteTable::Compile(services));
  return std::unique_ptr<Gateway>(
      new Gateway(std::move(routes), services, factory, std::move(channel), std::move(options)));
}

void Gateway::Register(httplib::Server& http) {
  RegisterPreRouting(http);
  http.set_error_handler(Server::HandlerWithResponse(AnswerHttplibError));
  http.set_exception_handler(AnswerException);
  http.Get("/openapi.json",
           [this](const httplib::Request&, httplib::Response& res) { res.set_content(openapi_, "application/json"); });
  // gRPC-Web first: its paths would otherwise reach the REST routes below.
  http.Post(R"(/[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z0-9_]+)+/[A-Za-z0-9_]+)",
            [this](const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader) {
              grpc_web_.Handle(req, res, reader);
            });
  auto plain = [this](const httplib::Request& req, httplib::Response& res) { HandleApiRequest(req, res, nullptr); };
  auto reading = [this](const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader) {
    HandleApiRequest(req, res, &reader);
  };
  http.Get(".*", plain);
  http.Post(".*", plain).Post(".*", reading);
  http.Put(".*", plain).Put(".*", reading);
  http.Patch(".*", plain).Patch(".*", reading);
  http.Delete(".*", plain).Delete(".*", reading);
}

void Gateway::RegisterPreRouting(httplib::Server& http) {
  http.set_pre_routing_handler([this](const httplib::Request& req, httplib::Response& res) {
    // httplib prefers brotli when offered, at quality 11: seconds for a
    // megabyte of JSON (a mesh's geometry took 6.0 s, against 0.8 s in gzip).
    // Offered brotli is dropped, so such clients (browsers) get gzip. The
    // request is httplib's own mutable object, handed over as const.
    DropBrotli(const_cast<httplib::Request&>(req).headers);
    cors_.Decorate(req, res);
    if (req.has_header("x-request-id")) res.set_header("x-request-id", req.get_header_value("x-request-id"));
    // Two Content-Length headers (or one beside Transfer-Encoding) could
    // frame the body differently here and in a proxy: refused unread.
    if (req.get_header_value_count("Content-Length") > 1 ||
        (req.has_header("Content-Length") && req.has_header("Transfer-Encoding"))) {
      res.set_header("Connection", "close");
      WriteError(res, 400, grpc::StatusCode::INVALID_ARGUMENT,
                 "request headers: more than one Content-Length, or Content-Length with Transfer-Encoding");
      return Server::HandlerResponse::Handled;
    }
    if (req.method != "OPTIONS") return Server::HandlerResponse::Unhandled;
    auto path = RequestPath::Parse(req.target);
    std::string allowed = grpc_web_.Serves(req.path) ? "POST" : path.ok() ? routes_.AllowedMethods(*path) : "";
    // Paths outside the API (health, viewer, openapi.json) are read-only.
    cors_.AnswerOptions(req, res, (allowed.empty() ? "GET, HEAD" : allowed) + ", OPTIONS");
    return Server::HandlerResponse::Handled;
  });
}

void Gateway::HandleApiRequest(const httplib::Request& req, httplib::Response& res,
                               const httplib::ContentReader* reader) {
  auto path = RequestPath::Parse(req.target);
  if (!path.ok()) return WriteError(res, 400, grpc::StatusCode::INVALID_ARGUMENT, path.status().message());
  if (IsWebSocketUpgrade(req)) return websocket_.Handle(req, res, *path);
  rest_.Handle(req, res, *path, reader);
}

}  // namespace armature::server::gateway
