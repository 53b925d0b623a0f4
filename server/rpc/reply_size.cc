#include "server/rpc/reply_size.h"

#include <cstdio>

namespace armature::server {
namespace {

// A float as protobuf's printer writes it, with its comma: from 2 bytes
// ("0,") to 16 ("-1.17549435e-38,"). demo_walk's poses take 794 bytes for
// 133 floats, skinned meshes about 12 a float. The estimate counts 5, the low
// end, so that answers that fit are not refused; the gateway's writer stops
// at the limit for those that take more than estimated.
constexpr double kJsonBytesPerFloat = 5;
constexpr double kJsonBytesPerDouble = 10;

std::string Mib(double bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", bytes / (1 << 20));
  return text;
}

}  // namespace

ReplyEncoding ReplyEncodingOf(const grpc::ServerContextBase& context) {
  const auto& metadata = context.client_metadata();
  const auto it = metadata.find(kReplyEncodingMetadata);
  return it != metadata.end() && it->second == "json" ? ReplyEncoding::kJson : ReplyEncoding::kProtobuf;
}

double ReplyContent::Bytes(ReplyEncoding encoding) const {
  if (encoding == ReplyEncoding::kJson)
    return floats * kJsonBytesPerFloat + doubles * kJsonBytesPerDouble + json_overhead;
  return floats * 4 + doubles * 8 + proto_overhead;
}

Status ValidateReplySize(const ReplyContent& reply, ReplyEncoding encoding, const Limits& limits,
                         const std::string& rpc, const std::string& alternative) {
  const double limit = static_cast<double>(limits.max_message_bytes);
  const double bytes = reply.Bytes(encoding);
  if (bytes <= limit) return Status::Ok();
  const bool json = encoding == ReplyEncoding::kJson;
  std::string message = rpc + ": the answer would take about " + Mib(bytes) + (json ? " as JSON" : "") + " (" +
                        reply.how + "), over the message limit of " + Mib(limit) + " (--max-message-mb); ask for less";
  const double binary = reply.Bytes(ReplyEncoding::kProtobuf);
  if (json && binary <= limit)
    message +=
        ", or for its binary encoding (" + Mib(binary) + "): header Accept: application/x-protobuf, or call over gRPC";
  if (!alternative.empty()) message += ", or " + alternative;
  return Status::ResourceExhausted(message);
}

}  // namespace armature::server
