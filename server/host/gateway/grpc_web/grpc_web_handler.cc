#include "server/host/gateway/grpc_web/grpc_web_handler.h"

#include <algorithm>
#include <cctype>

#include <httplib.h>

#include "server/host/gateway/common/error_mapping.h"
#include "server/host/gateway/common/request_headers.h"
#include "server/host/gateway/grpc_web/grpc_web_framing.h"

namespace armature::server::gateway {
namespace {

namespace pb = google::protobuf;

const char* ResponseType(bool text) { return text ? "application/grpc-web-text+proto" : "application/grpc-web+proto"; }

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

std::string GrpcMethodPath(const pb::MethodDescriptor& method) {
  return "/" + method.service()->full_name() + "/" + method.name();
}

}  // namespace

GrpcWebHandler::GrpcWebHandler(const std::vector<const pb::ServiceDescriptor*>& services, CallFactory& calls)
    : calls_(calls) {
  for (const auto* service : services)
    for (int i = 0; i < service->method_count(); ++i)
      methods_.emplace(GrpcMethodPath(*service->method(i)), service->method(i));
}

void GrpcWebHandler::Handle(const httplib::Request& req, httplib::Response& res, const httplib::ContentReader& reader) {
  const GrpcWebMode mode = GrpcWebModeOf(MediaType(req));
  if (mode == GrpcWebMode::kNone) {
    res.set_header("Connection", "close");  // the body is left unread
    return WriteError(res, 415, grpc::StatusCode::INVALID_ARGUMENT,
                      "POST " + req.path +
                          " is gRPC-Web: Content-Type must be application/grpc-web, application/grpc-web+proto or "
                          "application/grpc-web-text");
  }
  const bool text = mode == GrpcWebMode::kText;
  const auto found = methods_.find(req.path);
  if (found == methods_.end()) {
    res.set_header("Connection", "close");
    return AnswerStatus(res, text, grpc::Status(grpc::StatusCode::UNIMPLEMENTED, "no such method: " + req.path));
  }
  const pb::MethodDescriptor& method = *found->second;
  if (method.client_streaming()) {
    res.set_header("Connection", "close");
    return AnswerStatus(
        res, text,
        grpc::Status(grpc::StatusCode::UNIMPLEMENTED,
                     method.full_name() + " streams requests, which gRPC-Web over HTTP/1.1 cannot carry; call it over "
                                          "gRPC, or over a WebSocket on its REST path"));
  }
  // The token before the body, as REST does: a token-less request costs no memory.
  if (grpc::Status st = calls_.Authenticate(req.get_header_value("Authorization")); !st.ok()) {
    res.set_header("Connection", "close");
    return AnswerStatus(res, text, st);
  }
  std::string message;
  if (auto st = ReadRequestMessage(reader, text, method, res, &message); !st.ok()) return AnswerStatus(res, text, st);
  std::unique_ptr<grpc::ClientContext> context;
  if (auto st = calls_.MakeContext(req, method.server_streaming(), &context); !st.ok())
    return AnswerStatus(res, text, st);
  if (method.server_streaming()) return CallStreaming(method, text, std::move(context), std::move(message), res);
  CallUnary(method, text, std::move(context), std::move(message), res);
}

grpc::Status GrpcWebHandler::ReadRequestMessage(const httplib::ContentReader& reader, bool text,
                                                const pb::MethodDescriptor& method, httplib::Response& res,
                                                std::string* message) const {
  // The body, bounded: --max-request-kb of message (4/3 of it as base64).
  const size_t limit = calls_.options().max_request_bytes;
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
    return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED, "request body: more than " + std::to_string(body_limit) +
                                                                  " bytes; the request message is limited to " +
                                                                  std::to_string(limit) + " bytes (--max-request-kb)");
  }
  if (!complete) return Invalid("request body: could not be read (cut short?)");
  if (text) {
    std::string decoded;
    body.erase(std::remove_if(body.begin(), body.end(), [](unsigned char c) { return std::isspace(c); }), body.end());
    if (!Base64Decode(body, &decoded))
      return Invalid("request body: application/grpc-web-text takes base64 (padded groups)");
    body = std::move(decoded);
  }
  std::vector<std::string> messages;
  if (auto st = ParseGrpcWebFrames(body, limit, &messages); !st.ok()) return st;
  std::string().swap(body);
  if (messages.size() != 1)
    return Invalid("request body: " + method.full_name() + " takes exactly one message frame, got " +
                   std::to_string(messages.size()));
  // Checked here so that a bad encoding is named, not gRPC's "failed to parse".
  if (std::unique_ptr<pb::Message> probe(calls_.Prototype(method.input_type()).New());
      !probe->ParseFromString(messages[0]))
    return Invalid("request message: not a valid " + method.input_type()->full_name() + " encoding");
  *message = std::move(messages[0]);
  return grpc::Status::OK;
}

void GrpcWebHandler::CallUnary(const pb::MethodDescriptor& method, bool text,
                               std::unique_ptr<grpc::ClientContext> context, std::string request,
                               httplib::Response& res) {
  std::vector<std::string> responses;
  const grpc::Status status =
      calls_.CallWhole(GrpcMethodPath(method), std::move(context), {std::move(request)}, &responses);
  if (!status.ok()) return AnswerStatus(res, text, status);
  if (responses.size() != 1)
    return AnswerStatus(res, text,
                        grpc::Status(grpc::StatusCode::INTERNAL, method.full_name() + " returned " +
                                                                     std::to_string(responses.size()) + " responses"));
  AnswerMessage(res, text, responses[0]);
}

void GrpcWebHandler::CallStreaming(const pb::MethodDescriptor& method, bool text,
                                   std::unique_ptr<grpc::ClientContext> context, std::string request,
                                   httplib::Response& res) {
  std::shared_ptr<GenericCall> call;
  if (auto st = calls_.StartStream(GrpcMethodPath(method), std::move(context), {std::move(request)}, &call); !st.ok())
    return AnswerStatus(res, text, st);
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
      [&calls = calls_, state](bool) {
        if (state->closed) return;
        state->closed = true;
        state->call->Cancel();  // no-op when it already ended
        calls.EndStream(state->call.get());
      });
}

}  // namespace armature::server::gateway
