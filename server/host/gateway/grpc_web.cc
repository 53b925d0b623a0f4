// gRPC-Web on the HTTP port (Envoy's grpc-web filter, without the proxy):
// POST /armature.v1.<Service>/<Method> with Content-Type application/grpc-web
// (+proto) or application/grpc-web-text. The request frame's bytes are the
// request message, forwarded untouched over the gateway's in-process channel,
// so the auth gate, validation, limits and metrics of gRPC apply. Every answer
// is HTTP 200 with the status in a trailer frame at the end of the body;
// server streams write each message as a frame when it arrives (chunked).
#include <algorithm>
#include <cctype>

#include <httplib.h>

#include "server/host/gateway/error_mapping.h"
#include "server/host/gateway/gateway.h"
#include "server/host/gateway/generic_call.h"
#include "server/host/gateway/grpc_web_framing.h"

namespace armature::server::gateway {
namespace {

namespace pb = google::protobuf;

const char* ResponseType(bool text) {
  return text ? "application/grpc-web-text+proto" : "application/grpc-web+proto";
}

// The text mode encodes each write on its own (padded): clients decode the
// body as concatenated base64 chunks.
std::string Encoded(std::string frames, bool text) { return text ? Base64Encode(frames) : frames; }

void AnswerStatus(httplib::Response& res, bool text, const grpc::Status& status) {
  res.status = 200;
  res.set_content(Encoded(GrpcWebTrailerFrame(status), text), ResponseType(text));
}

void AnswerMessage(httplib::Response& res, bool text, const std::string& message) {
  std::string body;
  body.reserve(message.size() + 64);
  AppendGrpcWebFrame(kGrpcWebDataFlag, message, &body);
  body += GrpcWebTrailerFrame(grpc::Status::OK);
  res.status = 200;
  res.set_content(Encoded(std::move(body), text), ResponseType(text));
}

grpc::Status Invalid(const std::string& message) { return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, message); }

}  // namespace

void Gateway::HandleGrpcWeb(const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader) {
  const GrpcWebMode mode = GrpcWebModeOf(MediaType(req));
  if (mode == GrpcWebMode::kNone) {
    res.set_header("Connection", "close");  // the body is left unread
    return WriteError(res, 415, grpc::StatusCode::INVALID_ARGUMENT,
                      "POST " + req.path +
                          " is gRPC-Web: Content-Type must be application/grpc-web, application/grpc-web+proto or "
                          "application/grpc-web-text");
  }
  const bool text = mode == GrpcWebMode::kText;
  const auto found = grpc_web_methods_.find(req.path);
  if (found == grpc_web_methods_.end()) {
    res.set_header("Connection", "close");
    return AnswerStatus(res, text, grpc::Status(grpc::StatusCode::UNIMPLEMENTED, "no such method: " + req.path));
  }
  const pb::MethodDescriptor& method = *found->second;
  if (method.client_streaming()) {
    res.set_header("Connection", "close");
    return AnswerStatus(res, text,
                        grpc::Status(grpc::StatusCode::UNIMPLEMENTED,
                                     method.full_name() +
                                         " streams requests, which gRPC-Web over HTTP/1.1 cannot carry; call it over "
                                         "gRPC, or over a WebSocket on its REST path"));
  }
  // The token before the body, as REST does: a token-less request costs no memory.
  if (options_.tokens) {
    if (Status st = options_.tokens->Check(req.get_header_value("Authorization")); !st.ok()) {
      res.set_header("Connection", "close");
      return AnswerStatus(res, text, grpc::Status(grpc::StatusCode::UNAUTHENTICATED, st.message()));
    }
  }

  // The body, bounded: --max-request-kb of message (4/3 of it as base64).
  const size_t limit = options_.max_request_bytes;
  const size_t body_limit = kGrpcWebFrameHeaderBytes + (text ? (limit + kGrpcWebFrameHeaderBytes + 2) / 3 * 4 : limit);
  std::string body;
  bool too_large = false;
  const bool complete = reader([&](const char* data, size_t n) {
    if (body.size() + n > body_limit) {
      too_large = true;
      return false;
    }
    body.append(data, n);
    return true;
  });
  if (too_large) {
    res.set_header("Connection", "close");
    return AnswerStatus(res, text,
                        grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                                     "request body: more than " + std::to_string(body_limit) +
                                         " bytes; the request message is limited to " + std::to_string(limit) +
                                         " bytes (--max-request-kb)"));
  }
  if (!complete) return AnswerStatus(res, text, Invalid("request body: could not be read (cut short?)"));
  if (text) {
    std::string decoded;
    body.erase(std::remove_if(body.begin(), body.end(), [](unsigned char c) { return std::isspace(c); }), body.end());
    if (!Base64Decode(body, &decoded))
      return AnswerStatus(res, text, Invalid("request body: application/grpc-web-text takes base64 (padded groups)"));
    body = std::move(decoded);
  }
  std::vector<std::string> messages;
  if (auto st = ParseGrpcWebFrames(body, limit, &messages); !st.ok()) return AnswerStatus(res, text, st);
  std::string().swap(body);
  if (messages.size() != 1)
    return AnswerStatus(res, text,
                        Invalid("request body: " + method.full_name() + " takes exactly one message frame, got " +
                                std::to_string(messages.size())));
  // Checked here so that a bad encoding is named, not gRPC's "failed to parse".
  if (std::unique_ptr<pb::Message> probe(Prototype(method.input_type()).New()); !probe->ParseFromString(messages[0]))
    return AnswerStatus(res, text,
                        Invalid("request message: not a valid " + method.input_type()->full_name() + " encoding"));

  std::unique_ptr<grpc::ClientContext> context;
  if (auto st = MakeContext(req, method.server_streaming(), &context); !st.ok()) return AnswerStatus(res, text, st);
  const std::string grpc_method = "/" + method.service()->full_name() + "/" + method.name();
  if (method.server_streaming())
    return CallGrpcWebStreaming(method, text, std::move(context), std::move(messages[0]), res);

  auto call = GenericCall::Start(*stub_, grpc_method, std::move(context), {std::move(messages[0])});
  if (!calls_.Add(call.get()))
    return AnswerStatus(res, text, grpc::Status(grpc::StatusCode::UNAVAILABLE, "the server is shutting down"));
  std::vector<std::string> responses;
  const grpc::Status status = call->Drain(&responses);
  calls_.Remove(call.get());
  if (!status.ok()) return AnswerStatus(res, text, status);
  if (responses.size() != 1)
    return AnswerStatus(res, text,
                        grpc::Status(grpc::StatusCode::INTERNAL, method.full_name() + " returned " +
                                                                     std::to_string(responses.size()) + " responses"));
  AnswerMessage(res, text, responses[0]);
}

void Gateway::CallGrpcWebStreaming(const pb::MethodDescriptor& method, bool text,
                                   std::unique_ptr<grpc::ClientContext> context, std::string request,
                                   httplib::Response& res) {
  if (open_streams_.fetch_add(1) >= options_.max_streams) {
    --open_streams_;
    return AnswerStatus(res, text,
                        grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                                     "too many open streams (" + std::to_string(options_.max_streams) +
                                         "); try again later"));
  }
  const std::string grpc_method = "/" + method.service()->full_name() + "/" + method.name();
  std::shared_ptr<GenericCall> call = GenericCall::Start(*stub_, grpc_method, std::move(context), {std::move(request)});
  if (!calls_.Add(call.get())) {
    --open_streams_;
    return AnswerStatus(res, text, grpc::Status(grpc::StatusCode::UNAVAILABLE, "the server is shutting down"));
  }
  struct State {
    std::shared_ptr<GenericCall> call;
    bool closed = false;
  };
  auto state = std::make_shared<State>(State{std::move(call)});
  res.status = 200;
  res.set_header("Cache-Control", "no-cache");
  res.set_header("X-Accel-Buffering", "no");  // proxies must not buffer the stream
  res.set_chunked_content_provider(
      ResponseType(text),
      [state, text](size_t, httplib::DataSink& sink) -> bool {
        // No heartbeat: a vanished client shows up at the next frame's write.
        std::string message;
        if (state->call->Read(&message) == GenericCall::Next::kMessage) {
          std::string frame;
          AppendGrpcWebFrame(kGrpcWebDataFlag, message, &frame);
          const std::string out = Encoded(std::move(frame), text);
          return sink.write(out.data(), out.size());
        }
        const std::string out = Encoded(GrpcWebTrailerFrame(state->call->status()), text);
        if (!sink.write(out.data(), out.size())) return false;
        sink.done();
        return true;
      },
      [this, state](bool) {
        if (state->closed) return;
        state->closed = true;
        state->call->Cancel();  // no-op when it already ended
        calls_.Remove(state->call.get());
        --open_streams_;
      });
}

}  // namespace armature::server::gateway
