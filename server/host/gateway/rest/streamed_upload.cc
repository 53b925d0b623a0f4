// A raw upload body (POST /v1/assets:import with the file as the body) on its
// way to the client-streaming RPC: read chunk by chunk from httplib's
// ContentReader, each chunk sent on as a request while the next is read, so
// the gateway holds a chunk or two of it, not the body and its messages.
#include <algorithm>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <httplib.h>

#include "server/host/gateway/common/error_mapping.h"
#include "server/host/gateway/rest/request_body.h"
#include "server/host/gateway/rest/rest_handler.h"

namespace armature::server::gateway {

namespace pb = google::protobuf;

void RestHandler::StreamRawUpload(const httplib::Request& req, const HttpBinding& binding, const HttpRequestParts& http,
                                  const httplib::ContentReader& reader, uint64_t declared, httplib::Response& res) {
  const pb::Message& prototype = calls_.Prototype(binding.method->input_type());
  std::unique_ptr<pb::Message> first(prototype.New());
  grpc::Status st = ParamsMessage(binding, http, first.get());
  std::unique_ptr<grpc::ClientContext> context;
  if (st.ok()) st = calls_.MakeContext(req, false, &context);
  if (st.ok() && calls_.calls().draining()) st = ShuttingDown();
  if (!st.ok()) {  // answered from the headers: the body stays unread
    res.set_header("Connection", "close");
    return WriteError(res, st);
  }
  std::unique_ptr<GenericCall> call;
  if (st = calls_.StartUpload(binding.grpc_method(), std::move(context), &call); !st.ok()) {
    res.set_header("Connection", "close");
    return WriteError(res, st);
  }

  const pb::FieldDescriptor* data = binding.body_field.front();
  const GatewayOptions& options = calls_.options();
  const size_t chunk = options.upload_chunk_bytes > 0 ? options.upload_chunk_bytes : size_t{1} << 20;
  const size_t limit = options.max_upload_bytes;
  std::string pending;  // read, not yet sent
  size_t total = 0, dropped = 0;
  bool sent = false, over_limit = false, refused = false;
  auto send = [&](std::string_view bytes) {
    std::unique_ptr<pb::Message> m(first ? first.release() : prototype.New());
    m->GetReflection()->SetString(m.get(), data, std::string(bytes));
    sent = true;
    return call->Write(m->SerializeAsString());
  };
  // Once refused (over the limit, or the RPC answered early: too many
  // uploads, a bad name), the rest is read and dropped up to kDrainBytes.
  const bool complete = reader([&](const char* p, size_t n) {
    if (over_limit || refused) return (dropped += n) <= kDrainBytes;
    total += n;
    if (total > limit) {
      over_limit = true;
      return (dropped += n) <= kDrainBytes;
    }
    pending.append(p, n);
    size_t at = 0;
    for (; pending.size() - at >= chunk && !refused; at += chunk)
      refused = !send(std::string_view(pending).substr(at, chunk));
    pending.erase(0, at);
    return refused ? (dropped += pending.size()) <= kDrainBytes : true;
  });
  if (!complete) res.set_header("Connection", "close");
  if (over_limit || (!complete && !refused)) {
    call->Cancel();
    call->CloseWrites();
    std::vector<std::string> ignored;
    (void)call->Drain(&ignored);
    calls_.EndUpload(call.get());
    if (over_limit)
      return WriteError(res, 413, grpc::StatusCode::RESOURCE_EXHAUSTED,
                        TooLarge(std::max<size_t>(declared, total + dropped), limit, true));
    return WriteError(res, 400, grpc::StatusCode::INVALID_ARGUMENT, "request body: could not be read (cut short?)");
  }
  if (!refused && (!pending.empty() || !sent)) send(pending);  // the last chunk; an empty body sends its fields
  std::string().swap(pending);
  call->CloseWrites();
  std::vector<std::string> responses;
  const grpc::Status status = call->Drain(&responses);
  calls_.EndUpload(call.get());
  WriteUnaryAnswer(binding, status, std::move(responses), AcceptsProtobuf(req.get_header_value("Accept")), res);
}

}  // namespace armature::server::gateway
