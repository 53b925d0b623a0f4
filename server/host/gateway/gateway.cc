#include "server/host/gateway/gateway.h"

#include <algorithm>
#include <cctype>
#include <map>
#include <set>

#include <httplib.h>
#include <spdlog/spdlog.h>

#include "armature/base/utf8.h"
#include "server/host/gateway/error_mapping.h"
#include "server/host/gateway/generic_call.h"
#include "server/host/gateway/multipart_upload.h"
#include "server/host/gateway/openapi.h"
#include "server/host/gateway/sse.h"
#include "server/rpc/caller_identity.h"  // kRestPeerMetadata
#include "server/rpc/reply_size.h"       // kReplyEncodingMetadata
#include "server/rpc/streams/session_admission.h"

namespace armature::server::gateway {

std::string MediaType(const httplib::Request& req) {
  std::string type = req.get_header_value("Content-Type");
  type = type.substr(0, type.find(';'));
  type.erase(std::remove_if(type.begin(), type.end(), [](unsigned char c) { return std::isspace(c); }), type.end());
  std::transform(type.begin(), type.end(), type.begin(), [](unsigned char c) { return std::tolower(c); });
  return type;
}

namespace {

// Removes "br" from every Accept-Encoding header (see Register).
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
      const std::string coding = first == std::string::npos ? "" : token.substr(first, token.find_first_of(" \t;", first) - first);
      if (!coding.empty() && coding != "br") kept += (kept.empty() ? "" : ", ") + token.substr(first);
      start = comma + 1;
    }
    it->second = kept;
  }
}

namespace pb = google::protobuf;

// HTTP headers that travel to the gRPC handlers as metadata.
constexpr const char* kForwardedHeaders[] = {"authorization", "x-request-id", "traceparent", "tracestate"};

// gRPC's timeout header: up to 8 digits and a unit (H, M, S, m, u, n).
std::optional<std::chrono::nanoseconds> ParseGrpcTimeout(const std::string& text) {
  if (text.size() < 2 || text.size() > 9) return std::nullopt;
  int64_t value = 0;
  for (size_t i = 0; i + 1 < text.size(); ++i) {
    if (!std::isdigit(static_cast<unsigned char>(text[i]))) return std::nullopt;
    value = value * 10 + (text[i] - '0');
  }
  using namespace std::chrono;
  switch (text.back()) {
    case 'H': return hours(value);
    case 'M': return minutes(value);
    case 'S': return seconds(value);
    case 'm': return milliseconds(value);
    case 'u': return microseconds(value);
    case 'n': return nanoseconds(value);
    default: return std::nullopt;
  }
}

bool IsPrintableAscii(const std::string& s) {
  return std::all_of(s.begin(), s.end(), [](unsigned char c) { return c >= 0x20 && c < 0x7f; });
}

}  // namespace

grpc::Status ShuttingDown() { return grpc::Status(grpc::StatusCode::UNAVAILABLE, "the server is shutting down"); }

std::string TooLarge(size_t size, size_t limit, bool raw) {
  return "request body: " + std::to_string(size) + " bytes exceed the limit of " + std::to_string(limit) +
         " bytes (" + (raw ? "--max-upload-mb" : "--max-request-kb") + ")";
}

Gateway::Gateway(GatewayOptions options, pb::MessageFactory* factory, std::shared_ptr<grpc::Channel> channel)
    : options_(std::move(options)), factory_(factory), channel_(std::move(channel)),
      stub_(std::make_unique<grpc::GenericStub>(channel_)), cors_(options_.cors_origins) {}

StatusOr<std::unique_ptr<Gateway>> Gateway::Create(const std::vector<const pb::ServiceDescriptor*>& services,
                                                   pb::MessageFactory* factory, std::shared_ptr<grpc::Channel> channel,
                                                   GatewayOptions options) {
  std::unique_ptr<Gateway> g(new Gateway(std::move(options), factory, std::move(channel)));
  std::map<std::string, std::string> claimed;  // "GET /v1/x/{}" → method
  for (const auto* service : services) {
    for (int i = 0; i < service->method_count(); ++i) {
      g->grpc_web_methods_.emplace("/" + service->full_name() + "/" + service->method(i)->name(), service->method(i));
      auto bindings = BindingsOf(service->method(i));
      if (!bindings.ok()) return bindings.status();
      for (auto& b : *bindings) {
        const std::string key = b.http_method + " " + b.path.Simplified();
        if (auto [it, fresh] = claimed.emplace(key, b.method->full_name()); !fresh)
          return Status::InvalidArgument("(google.api.http): " + key + " is bound to both " + it->second + " and " +
                                         b.method->full_name());
        g->bindings_.push_back(std::move(b));
      }
    }
  }
  g->openapi_ = OpenApiDocument(g->bindings_, {}).dump(2);
  return g;
}

// A path can match several templates: "/v1/clips/a:evaluate" matches
// "/v1/clips/{clip}:evaluate" and, as a clip named "a:evaluate",
// "/v1/clips/{clip}". Only the most specific ones count, whatever their method.
std::vector<Gateway::Route> Gateway::BestMatches(const RequestPath& path) const {
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

std::optional<Gateway::Route> Gateway::Match(const std::string& http_method, const RequestPath& path) const {
  for (auto& route : BestMatches(path))
    if (route.binding->http_method == http_method) return std::move(route);
  return std::nullopt;
}

std::string Gateway::AllowedMethods(const RequestPath& path) const {
  std::set<std::string> methods;
  for (const auto& route : BestMatches(path)) methods.insert(route.binding->http_method);
  if (methods.count("GET")) methods.insert("HEAD");
  std::string out;
  for (const auto& m : methods) out += (out.empty() ? "" : ", ") + m;
  return out;
}

size_t Gateway::BodyLimit(const HttpBinding& binding, const std::string& content_type) const {
  return IsRawBytesBody(binding, content_type) ? options_.max_upload_bytes : options_.max_request_bytes;
}

grpc::Status Gateway::MakeContext(const httplib::Request& req, bool server_streaming,
                                  std::unique_ptr<grpc::ClientContext>* context) const {
  auto ctx = std::make_unique<grpc::ClientContext>();
  std::optional<std::chrono::nanoseconds> timeout;
  if (req.has_header("grpc-timeout")) {
    timeout = ParseGrpcTimeout(req.get_header_value("grpc-timeout"));
    if (!timeout)
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          "header grpc-timeout: expected up to 8 digits and a unit H, M, S, m, u or n, e.g. 500m");
  } else if (!server_streaming) {
    timeout = options_.default_timeout;
  }
  if (timeout)
    ctx->set_deadline(std::chrono::system_clock::now() +
                      std::chrono::duration_cast<std::chrono::system_clock::duration>(*timeout));
  for (const char* name : kForwardedHeaders) {
    if (!req.has_header(name)) continue;
    const std::string value = req.get_header_value(name);
    if (!IsPrintableAscii(value))
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, std::string("header ") + name + ": must be printable ASCII");
    ctx->AddMetadata(name, value);
  }
  // Per-client limits (streams, sessions) count each HTTP client apart; behind
  // a trusted proxy, the client it names.
  std::string forwarded_for;
  for (size_t i = 0; i < req.get_header_value_count("X-Forwarded-For"); ++i) {
    if (i > 0) forwarded_for += ',';  // appended apart: GCC 12's false -Wrestrict on "," + std::string&&
    forwarded_for += req.get_header_value("X-Forwarded-For", i);
  }
  ctx->AddMetadata(kRestPeerMetadata, options_.trusted_proxies.ClientOf(req.remote_addr, forwarded_for));
  *context = std::move(ctx);
  return grpc::Status::OK;
}

void Gateway::Register(httplib::Server& http) {
  using httplib::Server;
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
    std::string allowed = grpc_web_methods_.count(req.path) ? "POST" : path.ok() ? AllowedMethods(*path) : "";
    // Paths outside the API (health, viewer, openapi.json) are read-only.
    cors_.AnswerOptions(req, res, (allowed.empty() ? "GET, HEAD" : allowed) + ", OPTIONS");
    return Server::HandlerResponse::Handled;
  });
  // Errors cpp-httplib produces itself (bad request line, oversized URI) get the JSON shape too.
  http.set_error_handler(Server::HandlerWithResponse([](const httplib::Request&, httplib::Response& res) {
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
  }));
  // The exception boundary of REST handlers (see server/rpc/call_guard.h for gRPC's).
  http.set_exception_handler([](const httplib::Request& req, httplib::Response& res, std::exception_ptr ep) {
    std::string what = "unknown exception";
    bool out_of_memory = false;
    try {
      std::rethrow_exception(ep);
    } catch (const std::bad_alloc&) {
      out_of_memory = true;
      what = "out of memory";
    } catch (const std::exception& e) {
      what = EscapeForMessage(e.what(), 1024);
    } catch (...) {
    }
    const std::string id = req.has_header("x-request-id") ? EscapeForMessage(req.get_header_value("x-request-id")) : "-";
    spdlog::error("gateway: {} {} (request {}): {}", req.method, EscapeForMessage(req.path, 256), id, what);
    if (out_of_memory)
      return WriteError(res, 503, grpc::StatusCode::RESOURCE_EXHAUSTED,
                        "the server ran out of memory serving this request; try a smaller one");
    WriteError(res, 500, grpc::StatusCode::INTERNAL, "internal error: " + what);
  });

  http.Get("/openapi.json", [this](const httplib::Request&, httplib::Response& res) {
    res.set_content(openapi_, "application/json");
  });
  // gRPC-Web first: its paths would otherwise reach the REST routes below.
  http.Post(R"(/[A-Za-z_][A-Za-z0-9_]*(\.[A-Za-z0-9_]+)+/[A-Za-z0-9_]+)",
            [this](const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader) {
              HandleGrpcWeb(req, res, reader);
            });
  auto plain = [this](const httplib::Request& req, httplib::Response& res) { Handle(req, res, nullptr); };
  auto reading = [this](const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader) {
    Handle(req, res, &reader);
  };
  http.Get(".*", plain);
  http.Post(".*", plain).Post(".*", reading);
  http.Put(".*", plain).Put(".*", reading);
  http.Patch(".*", plain).Patch(".*", reading);
  http.Delete(".*", plain).Delete(".*", reading);
}

void Gateway::Handle(const httplib::Request& req, httplib::Response& res, const httplib::ContentReader* reader) {
  auto path = RequestPath::Parse(req.target);
  if (!path.ok()) return WriteError(res, 400, grpc::StatusCode::INVALID_ARGUMENT, path.status().message());
  if (IsWebSocketUpgrade(req)) return HandleWebSocket(req, res, *path);
  const std::string method = req.method == "HEAD" ? "GET" : req.method;
  auto route = Match(method, *path);
  if (!route) {
    const std::string allowed = AllowedMethods(*path);
    if (allowed.empty())
      return WriteError(res, 404, grpc::StatusCode::NOT_FOUND, "no such resource: " + req.method + " " + req.path);
    res.set_header("Allow", allowed + ", OPTIONS");
    return WriteError(res, 405, grpc::StatusCode::UNIMPLEMENTED,
                      req.method + " is not allowed on " + req.path + " (allowed: " + allowed + ")");
  }
  const HttpBinding& binding = *route->binding;
  // Authentication before the body is read: an unauthenticated upload is
  // answered from its headers and its connection closed unread.
  if (options_.tokens) {
    if (Status st = options_.tokens->Check(req.get_header_value("Authorization")); !st.ok()) {
      if (reader) res.set_header("Connection", "close");
      return WriteError(res, grpc::Status(grpc::StatusCode::UNAUTHENTICATED, st.message()));
    }
  }

  HttpRequestParts parts;
  parts.path = std::move(route->variables);
  parts.content_type = MediaType(req);
  for (const auto& [k, v] : req.params) parts.query.emplace_back(k, v);
  const size_t limit = BodyLimit(binding, parts.content_type);
  const bool raw = IsRawBytesBody(binding, parts.content_type);
  // An oversized body is still read (and dropped) up to kDrainBytes past the
  // limit, so the connection stays in step for the next request; beyond
  // that the client gets its 413 without being read.
  const uint64_t declared = req.get_header_value<uint64_t>("Content-Length");
  if (declared > limit + kDrainBytes) {
    res.set_header("Connection", "close");
    return WriteError(res, 413, grpc::StatusCode::RESOURCE_EXHAUSTED, TooLarge(declared, limit, raw));
  }
  if (parts.content_type == "multipart/form-data" || req.is_multipart_form_data()) {
    if (!req.is_multipart_form_data()) {  // cpp-httplib parses forms only when it is spelled so
      res.set_header("Connection", "close");
      return WriteError(res, 400, grpc::StatusCode::INVALID_ARGUMENT,
                        "header Content-Type: write multipart/form-data in lower case, with its boundary");
    }
    std::vector<std::string> requests;
    if (ReadMultipartUpload(binding, reader, declared, parts, res, &requests)) Dispatch(req, binding, std::move(requests), res);
    return;
  }
  // A file upload goes on to the RPC as it arrives, never held whole here.
  if (reader && raw && binding.client_streaming()) return StreamRawUpload(req, binding, parts, *reader, declared, res);
  std::string body;
  if (reader) {
    size_t dropped = 0;
    const bool complete = (*reader)([&](const char* data, size_t n) {
      if (dropped == 0 && body.size() + n <= limit) {
        body.append(data, n);
        return true;
      }
      dropped += n;
      return dropped <= kDrainBytes;
    });
    if (dropped > 0 || res.status == 413) {
      if (!complete) res.set_header("Connection", "close");
      return WriteError(res, 413, grpc::StatusCode::RESOURCE_EXHAUSTED,
                        TooLarge(std::max<size_t>(declared, body.size() + dropped), limit, raw));
    }
    if (!complete)
      return WriteError(res, 400, grpc::StatusCode::INVALID_ARGUMENT, "request body: could not be read (cut short?)");
  } else {
    body = req.body;
    if (body.size() > limit)
      return WriteError(res, 413, grpc::StatusCode::RESOURCE_EXHAUSTED, TooLarge(body.size(), limit, raw));
  }
  parts.body = body;

  std::vector<std::string> requests;
  if (auto st = TranscodeRequest(binding, Prototype(binding.method->input_type()), parts,
                                 options_.upload_chunk_bytes, &requests);
      !st.ok())
    return WriteError(res, st);
  Dispatch(req, binding, std::move(requests), res);
}

bool Gateway::ReadMultipartUpload(const HttpBinding& binding, const httplib::ContentReader* reader, uint64_t declared,
                                  const HttpRequestParts& http, httplib::Response& res,
                                  std::vector<std::string>* requests) {
  if (!reader || !AcceptsMultipartUpload(binding)) {
    res.set_header("Connection", "close");
    WriteError(res, 415, grpc::StatusCode::INVALID_ARGUMENT,
               "request body: " + binding.http_method + " " + binding.path.text() +
                   " does not take multipart/form-data (only file uploads such as POST /v1/assets:import do)");
    return false;
  }
  std::vector<FormPart> form;
  bool unread_left = false;
  const grpc::Status read = ReadMultipartForm(*reader, options_.max_upload_bytes, kDrainBytes, &form, &unread_left);
  if (unread_left) res.set_header("Connection", "close");
  if (res.status == 413) {  // cpp-httplib's own cap, the payload max length
    WriteError(res, 413, grpc::StatusCode::RESOURCE_EXHAUSTED, TooLarge(declared, options_.max_upload_bytes, true));
    return false;
  }
  if (!read.ok()) {
    if (read.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED)
      WriteError(res, 413, read.error_code(), read.error_message());
    else
      WriteError(res, read);
    return false;
  }
  const grpc::Status st = TranscodeMultipartUpload(binding, Prototype(binding.method->input_type()), http,
                                                   std::move(form), options_.upload_chunk_bytes, requests);
  if (!st.ok()) WriteError(res, st);
  return st.ok();
}

void Gateway::Dispatch(const httplib::Request& req, const HttpBinding& binding, std::vector<std::string> requests,
                       httplib::Response& res) {
  std::unique_ptr<grpc::ClientContext> context;
  if (auto st = MakeContext(req, binding.server_streaming(), &context); !st.ok()) return WriteError(res, st);
  if (calls_.draining()) return WriteError(res, ShuttingDown());
  const bool proto_response = !binding.server_streaming() && AcceptsProtobuf(req.get_header_value("Accept"));
  // The handlers bound the answer in the encoding it is sent in.
  if (!proto_response) context->AddMetadata(kReplyEncodingMetadata, "json");
  if (binding.server_streaming())
    CallStreaming(binding, std::move(context), std::move(requests), res);
  else
    CallUnary(binding, std::move(context), std::move(requests), proto_response, res);
}

void Gateway::CallUnary(const HttpBinding& binding, std::unique_ptr<grpc::ClientContext> context,
                        std::vector<std::string> requests, bool proto_response, httplib::Response& res) {
  auto call = GenericCall::Start(*stub_, binding.grpc_method(), std::move(context), std::move(requests));
  if (!calls_.Add(call.get())) return WriteError(res, ShuttingDown());
  std::vector<std::string> responses;
  const grpc::Status status = call->Drain(&responses);
  calls_.Remove(call.get());
  WriteUnaryAnswer(binding, status, std::move(responses), proto_response, res);
}

void Gateway::WriteUnaryAnswer(const HttpBinding& binding, const grpc::Status& status,
                               std::vector<std::string> responses, bool proto_response, httplib::Response& res) {
  if (!status.ok()) return WriteError(res, status);
  if (responses.size() != 1)
    return WriteError(res, grpc::Status(grpc::StatusCode::INTERNAL, binding.method->full_name() + " returned " +
                                                                        std::to_string(responses.size()) + " responses"));
  if (proto_response) {  // Accept: application/x-protobuf, the response's own encoding
    res.status = 200;
    return res.set_content(std::move(responses[0]), kProtobufMediaType);
  }
  HttpBody body;
  if (auto st = TranscodeResponse(binding, Prototype(binding.method->output_type()), std::move(responses[0]),
                                 options_.max_reply_bytes, &body);
      !st.ok())
    return WriteError(res, st);
  res.status = 200;
  res.set_content(std::move(body.content), body.content_type);
}

void Gateway::CallStreaming(const HttpBinding& binding, std::unique_ptr<grpc::ClientContext> context,
                            std::vector<std::string> requests, httplib::Response& res) {
  if (open_streams_.fetch_add(1) >= options_.max_streams) {
    --open_streams_;
    return WriteError(res, grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                                        "too many open streams (" + std::to_string(options_.max_streams) +
                                            "); try again later"));
  }
  std::shared_ptr<GenericCall> call =
      GenericCall::Start(*stub_, binding.grpc_method(), std::move(context), std::move(requests));
  if (!calls_.Add(call.get())) {
    --open_streams_;
    return WriteError(res, ShuttingDown());
  }
  SseStream stream;
  // Wait briefly for the first response so that a request the handler
  // rejects outright gets a real HTTP error status.
  std::string first;
  switch (call->Read(&first, options_.first_response_wait)) {
    case GenericCall::Next::kMessage: stream.already_read.push_back(std::move(first)); break;
    case GenericCall::Next::kEnd:
      if (!call->status().ok()) {
        --open_streams_;
        calls_.Remove(call.get());
        return WriteError(res, call->status());
      }
      break;
    case GenericCall::Next::kTimeout: break;
  }
  const pb::Message* prototype = &Prototype(binding.method->output_type());
  stream.to_json = [&binding, prototype, max_bytes = options_.max_reply_bytes](const std::string& serialized) {
    HttpBody body;
    const grpc::Status st = TranscodeResponse(binding, *prototype, serialized, max_bytes, &body);
    return st.ok() ? body.content : ErrorJson(st.error_code(), st.error_message());
  };
  stream.heartbeat = options_.sse_heartbeat;
  stream.on_close = [this, raw = call.get()] {
    calls_.Remove(raw);
    --open_streams_;
  };
  stream.call = std::move(call);
  SendSse(res, std::move(stream));
}

}  // namespace armature::server::gateway
