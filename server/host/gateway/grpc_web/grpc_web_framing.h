// gRPC-Web's wire format, pure (no HTTP, no gRPC calls): each message is a
// frame of one flag byte (0x00 data, 0x80 trailers, bit 0x01 compressed) and
// a 4-byte big-endian length; the status travels in a last trailer frame,
// "grpc-status: N\r\ngrpc-message: <percent-encoded>\r\n". The text mode
// (application/grpc-web-text) is the same bytes in base64, each chunk padded.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include <grpcpp/grpcpp.h>

namespace armature::server::gateway {

inline constexpr uint8_t kGrpcWebDataFlag = 0x00;
inline constexpr uint8_t kGrpcWebCompressedFlag = 0x01;
inline constexpr uint8_t kGrpcWebTrailerFlag = 0x80;
inline constexpr size_t kGrpcWebFrameHeaderBytes = 5;

// Flag byte and length prefix, then `payload`, appended to `out`.
void AppendGrpcWebFrame(uint8_t flag, std::string_view payload, std::string* out);
// The trailer frame carrying `status` (message percent-encoded).
std::string GrpcWebTrailerFrame(const grpc::Status& status);

// grpc-message's encoding: bytes outside printable ASCII and '%' as %XX.
std::string PercentEncode(std::string_view text);
std::string PercentDecode(std::string_view text);

// The data frames of a request body, in order. INVALID_ARGUMENT for a
// truncated frame or a trailer frame, UNIMPLEMENTED for a compressed one,
// RESOURCE_EXHAUSTED for a frame longer than `max_message_bytes`.
grpc::Status ParseGrpcWebFrames(std::string_view body, size_t max_message_bytes, std::vector<std::string>* messages);

// Standard base64 with padding. Decoding takes concatenated padded chunks
// (each 4-character group may end in '='); false on any other character,
// on a group cut short or on padding inside a group.
std::string Base64Encode(std::string_view bytes);
bool Base64Decode(std::string_view text, std::string* out);

// "application/grpc-web", "application/grpc-web+proto" → kBinary,
// "application/grpc-web-text", "application/grpc-web-text+proto" → kText
// (media type lower case, without parameters), anything else → kNone.
enum class GrpcWebMode { kNone, kBinary, kText };
GrpcWebMode GrpcWebModeOf(const std::string& media_type);

}  // namespace armature::server::gateway
