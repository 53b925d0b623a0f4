#include "server/host/gateway/rest/rest_handler.h"

#include <httplib.h>

#include "server/host/gateway/common/error_mapping.h"
#include "server/host/gateway/common/request_headers.h"
#include "server/host/gateway/rest/multipart_upload.h"
#include "server/host/gateway/rest/request_body.h"
#include "server/host/gateway/rest/sse.h"
#include "server/rpc/reply_size.h"  // kReplyEncodingMetadata

namespace armature::server::gateway {

namespace pb = google::protobuf;

void RestHandler::Handle(const httplib::Request& req, httplib::Response& res, const RequestPath& path,
                         const httplib::ContentReader* reader) {
  const std::string method = req.method == "HEAD" ? "GET" : req.method;
  auto route = routes_.Match(method, path);
  if (!route) {
    const std::string allowed = routes_.AllowedMethods(path);
    if (allowed.empty())
      return WriteError(res, 404, grpc::StatusCode::NOT_FOUND, "no such resource: " + req.method + " " + req.path);
    res.set_header("Allow", allowed + ", OPTIONS");
    return WriteError(res, 405, grpc::StatusCode::UNIMPLEMENTED,
                      req.method + " is not allowed on " + req.path + " (allowed: " + allowed + ")");
  }
  const HttpBinding& binding = *route->binding;
  // Authentication before the body is read: an unauthenticated upload is
  // answered from its headers and its connection closed unread.
  if (grpc::Status st = calls_.Authenticate(req.get_header_value("Authorization")); !st.ok()) {
    if (reader) res.set_header("Connection", "close");
    return WriteError(res, st);
  }

  HttpRequestParts parts;
  parts.path = std::move(route->variables);
  parts.content_type = MediaType(req);
  for (const auto& [k, v] : req.params) parts.query.emplace_back(k, v);
  const size_t limit = BodyLimit(binding, parts.content_type);
  const bool raw = IsRawBytesBody(binding, parts.content_type);
  // Past kDrainBytes over the limit the client gets its 413 unread (request_body.h).
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
    if (ReadMultipartUpload(binding, reader, declared, parts, res, &requests))
      Dispatch(req, binding, std::move(requests), res);
    return;
  }
  // A file upload goes on to the RPC as it arrives, never held whole here.
  if (reader && raw && binding.client_streaming()) return StreamRawUpload(req, binding, parts, *reader, declared, res);
  std::string body;
  if (!ReadBoundedBody(req, reader, limit, declared, raw, res, &body)) return;
  parts.body = body;

  std::vector<std::string> requests;
  if (auto st = TranscodeRequest(binding, calls_.Prototype(binding.method->input_type()), parts,
                                 calls_.options().upload_chunk_bytes, &requests);
      !st.ok())
    return WriteError(res, st);
  Dispatch(req, binding, std::move(requests), res);
}

size_t RestHandler::BodyLimit(const HttpBinding& binding, const std::string& content_type) const {
  return IsRawBytesBody(binding, content_type) ? calls_.options().max_upload_bytes : calls_.options().max_request_bytes;
}

bool RestHandler::ReadMultipartUpload(const HttpBinding& binding, const httplib::ContentReader* reader,
                                      uint64_t declared, const HttpRequestParts& http, httplib::Response& res,
                                      std::vector<std::string>* requests) {
  if (!reader || !AcceptsMultipartUpload(binding)) {
    res.set_header("Connection", "close");
    WriteError(res, 415, grpc::StatusCode::INVALID_ARGUMENT,
               "request body: " + binding.http_method + " " + binding.path.text() +
                   " does not take multipart/form-data (only file uploads such as POST /v1/assets:import do)");
    return false;
  }
  const size_t max_upload_bytes = calls_.options().max_upload_bytes;
  std::vector<FormPart> form;
  bool unread_left = false;
  const grpc::Status read = ReadMultipartForm(*reader, max_upload_bytes, kDrainBytes, &form, &unread_left);
  if (unread_left) res.set_header("Connection", "close");
  if (res.status == 413) {  // cpp-httplib's own cap, the payload max length
    WriteError(res, 413, grpc::StatusCode::RESOURCE_EXHAUSTED, TooLarge(declared, max_upload_bytes, true));
    return false;
  }
  if (!read.ok()) {
    if (read.error_code() == grpc::StatusCode::RESOURCE_EXHAUSTED)
      WriteError(res, 413, read.error_code(), read.error_message());
    else
      WriteError(res, read);
    return false;
  }
  const grpc::Status st = TranscodeMultipartUpload(binding, calls_.Prototype(binding.method->input_type()), http,
                                                   std::move(form), calls_.options().upload_chunk_bytes, requests);
  if (!st.ok()) WriteError(res, st);
  return st.ok();
}

void RestHandler::Dispatch(const httplib::Request& req, const HttpBinding& binding, std::vector<std::string> requests,
                           httplib::Response& res) {
  std::unique_ptr<grpc::ClientContext> context;
  if (auto st = calls_.MakeContext(req, binding.server_streaming(), &context); !st.ok()) return WriteError(res, st);
  if (calls_.calls().draining()) return WriteError(res, ShuttingDown());
  const bool proto_response = !binding.server_streaming() && AcceptsProtobuf(req.get_header_value("Accept"));
  // The handlers bound the answer in the encoding it is sent in.
  if (!proto_response) context->AddMetadata(kReplyEncodingMetadata, "json");
  if (binding.server_streaming()) return CallStreaming(binding, std::move(context), std::move(requests), res);
  std::vector<std::string> responses;
  const grpc::Status status =
      calls_.CallWhole(binding.grpc_method(), std::move(context), std::move(requests), &responses);
  WriteUnaryAnswer(binding, status, std::move(responses), proto_response, res);
}

void RestHandler::WriteUnaryAnswer(const HttpBinding& binding, const grpc::Status& status,
                                   std::vector<std::string> responses, bool proto_response, httplib::Response& res) {
  if (!status.ok()) return WriteError(res, status);
  if (responses.size() != 1)
    return WriteError(res,
                      grpc::Status(grpc::StatusCode::INTERNAL, binding.method->full_name() + " returned " +
                                                                   std::to_string(responses.size()) + " responses"));
  if (proto_response) {  // Accept: application/x-protobuf, the response's own encoding
    res.status = 200;
    return res.set_content(std::move(responses[0]), kProtobufMediaType);
  }
  HttpBody body;
  if (auto st = TranscodeResponse(binding, calls_.Prototype(binding.method->output_type()), std::move(responses[0]),
                                  calls_.options().max_reply_bytes, &body);
      !st.ok())
    return WriteError(res, st);
  res.status = 200;
  res.set_content(std::move(body.content), body.content_type);
}

void RestHandler::CallStreaming(const HttpBinding& binding, std::unique_ptr<grpc::ClientContext> context,
                                std::vector<std::string> requests, httplib::Response& res) {
  std::shared_ptr<GenericCall> call;
  if (auto st = calls_.StartStream(binding.grpc_method(), std::move(context), std::move(requests), &call); !st.ok())
    return WriteError(res, st);
  SseStream stream;
  // Wait briefly for the first response so that a request the handler
  // rejects outright gets a real HTTP error status.
  std::string first;
  switch (call->Read(&first, calls_.options().first_response_wait)) {
    case GenericCall::Next::kMessage: stream.already_read.push_back(std::move(first)); break;
    case GenericCall::Next::kEnd:
      if (!call->status().ok()) {
        calls_.EndStream(call.get());
        return WriteError(res, call->status());
      }
      break;
    case GenericCall::Next::kTimeout: break;
  }
  const pb::Message* prototype = &calls_.Prototype(binding.method->output_type());
  stream.to_json = [&binding, prototype, max_bytes = calls_.options().max_reply_bytes](const std::string& serialized) {
    HttpBody body;
    const grpc::Status st = TranscodeResponse(binding, *prototype, serialized, max_bytes, &body);
    return st.ok() ? body.content : ErrorJson(st.error_code(), st.error_message());
  };
  stream.heartbeat = calls_.options().sse_heartbeat;
  stream.on_close = [&calls = calls_, raw = call.get()] { calls.EndStream(raw); };
  stream.call = std::move(call);
  SendSse(res, std::move(stream));
}

}  // namespace armature::server::gateway
