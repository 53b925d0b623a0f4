// An answer's size, estimated before any work, in the encoding it will be
// sent in: protobuf over gRPC, gRPC-Web and REST with Accept:
// application/x-protobuf; JSON over REST otherwise, which the gateway says in
// the call's metadata. JSON takes 1.5 to 3 times the bytes of protobuf (a
// float's 4 bytes become up to 9 digits, sign, point and comma).
#pragma once

#include <string>

#include <grpcpp/grpcpp.h>

#include "armature/base/status.h"
#include "server/rpc/limits.h"

namespace armature::server {

enum class ReplyEncoding { kProtobuf, kJson };

// Metadata the REST gateway sets on calls it will answer in JSON: "json".
inline constexpr char kReplyEncodingMetadata[] = "x-armature-reply-encoding";
ReplyEncoding ReplyEncodingOf(const grpc::ServerContextBase& context);

// What an answer holds, counted before the work.
struct ReplyContent {
  double floats = 0;          // float values
  double doubles = 0;         // double values
  double proto_overhead = 0;  // the rest in protobuf: tags, lengths, integers, names
  double json_overhead = 0;   // the rest in JSON: field names, brackets, integers, names
  std::string how;            // what was counted, e.g. "100000 times x 31 joints"

  double Bytes(ReplyEncoding encoding) const;
};

// RESOURCE_EXHAUSTED when the answer would pass --max-message-mb in
// `encoding`, naming the limit, the estimate and, for JSON, the binary
// encoding's size and `alternative` (e.g. the streaming call) when given.
Status ValidateReplySize(const ReplyContent& reply, ReplyEncoding encoding, const Limits& limits,
                         const std::string& rpc, const std::string& alternative = "");

}  // namespace armature::server
