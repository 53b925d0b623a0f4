#include "server/host/gateway/grpc_web/grpc_web_framing.h"

#include <array>

namespace armature::server::gateway {
namespace {

constexpr char kBase64Alphabet[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

constexpr std::array<int8_t, 256> Base64Values() {
  std::array<int8_t, 256> v{};
  for (auto& x : v) x = -1;
  for (int i = 0; i < 64; ++i) v[static_cast<unsigned char>(kBase64Alphabet[i])] = static_cast<int8_t>(i);
  return v;
}
constexpr std::array<int8_t, 256> kBase64Values = Base64Values();

int HexValue(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  return -1;
}

}  // namespace

void AppendGrpcWebFrame(uint8_t flag, std::string_view payload, std::string* out) {
  const auto n = static_cast<uint32_t>(payload.size());
  const char header[kGrpcWebFrameHeaderBytes] = {static_cast<char>(flag), static_cast<char>(n >> 24),
                                                 static_cast<char>(n >> 16), static_cast<char>(n >> 8),
                                                 static_cast<char>(n)};
  out->reserve(out->size() + sizeof(header) + payload.size());
  out->append(header, sizeof(header));
  out->append(payload.data(), payload.size());
}

std::string GrpcWebTrailerFrame(const grpc::Status& status) {
  const std::string trailers = "grpc-status: " + std::to_string(static_cast<int>(status.error_code())) +
                               "\r\ngrpc-message: " + PercentEncode(status.error_message()) + "\r\n";
  std::string frame;
  AppendGrpcWebFrame(kGrpcWebTrailerFlag, trailers, &frame);
  return frame;
}

std::string PercentEncode(std::string_view text) {
  static constexpr char kHex[] = "0123456789ABCDEF";
  std::string out;
  out.reserve(text.size());
  for (const char ch : text) {
    const auto c = static_cast<unsigned char>(ch);
    if (c >= 0x20 && c < 0x7f && c != '%') {
      out += ch;
    } else {
      out += '%';
      out += kHex[c >> 4];
      out += kHex[c & 0xf];
    }
  }
  return out;
}

std::string PercentDecode(std::string_view text) {
  std::string out;
  out.reserve(text.size());
  for (size_t i = 0; i < text.size(); ++i) {
    if (text[i] == '%' && i + 2 < text.size() && HexValue(text[i + 1]) >= 0 && HexValue(text[i + 2]) >= 0) {
      out += static_cast<char>(HexValue(text[i + 1]) * 16 + HexValue(text[i + 2]));
      i += 2;
    } else {
      out += text[i];  // a lone '%' stays as it is, as gRPC's decoder does
    }
  }
  return out;
}

grpc::Status ParseGrpcWebFrames(std::string_view body, size_t max_message_bytes, std::vector<std::string>* messages) {
  messages->clear();
  size_t offset = 0;
  while (offset < body.size()) {
    const std::string where =
        "gRPC-Web frame " + std::to_string(messages->size() + 1) + " at byte " + std::to_string(offset);
    if (body.size() - offset < kGrpcWebFrameHeaderBytes)
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          where + ": " + std::to_string(body.size() - offset) +
                              " bytes are too few for the 5-byte header (flag, length)");
    const auto flag = static_cast<uint8_t>(body[offset]);
    uint32_t length = 0;
    for (size_t i = 1; i < kGrpcWebFrameHeaderBytes; ++i)
      length = (length << 8) | static_cast<unsigned char>(body[offset + i]);
    if (flag & kGrpcWebTrailerFlag)
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, where + ": a trailer frame (flag 0x80) in a request");
    if (flag & kGrpcWebCompressedFlag)
      return grpc::Status(grpc::StatusCode::UNIMPLEMENTED,
                          where + ": compressed messages are not supported (send grpc-encoding identity)");
    if (flag != kGrpcWebDataFlag)
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, where + ": unknown flag byte " + std::to_string(flag));
    if (length > max_message_bytes)
      return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED, where + ": its length " + std::to_string(length) +
                                                                    " exceeds the limit of " +
                                                                    std::to_string(max_message_bytes) + " bytes");
    offset += kGrpcWebFrameHeaderBytes;
    if (body.size() - offset < length)
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          where + ": its length prefix says " + std::to_string(length) + " bytes but only " +
                              std::to_string(body.size() - offset) + " follow (truncated?)");
    messages->emplace_back(body.substr(offset, length));
    offset += length;
  }
  return grpc::Status::OK;
}

std::string Base64Encode(std::string_view bytes) {
  std::string out;
  out.reserve((bytes.size() + 2) / 3 * 4);
  size_t i = 0;
  for (; i + 3 <= bytes.size(); i += 3) {
    const uint32_t v = (static_cast<unsigned char>(bytes[i]) << 16) | (static_cast<unsigned char>(bytes[i + 1]) << 8) |
                       static_cast<unsigned char>(bytes[i + 2]);
    out += kBase64Alphabet[(v >> 18) & 63];
    out += kBase64Alphabet[(v >> 12) & 63];
    out += kBase64Alphabet[(v >> 6) & 63];
    out += kBase64Alphabet[v & 63];
  }
  if (const size_t rest = bytes.size() - i; rest > 0) {
    uint32_t v = static_cast<unsigned char>(bytes[i]) << 16;
    if (rest == 2) v |= static_cast<unsigned char>(bytes[i + 1]) << 8;
    out += kBase64Alphabet[(v >> 18) & 63];
    out += kBase64Alphabet[(v >> 12) & 63];
    out += rest == 2 ? kBase64Alphabet[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

bool Base64Decode(std::string_view text, std::string* out) {
  out->clear();
  if (text.size() % 4 != 0) return false;
  out->reserve(text.size() / 4 * 3);
  for (size_t i = 0; i < text.size(); i += 4) {
    int v[4];
    int padding = 0;
    for (int k = 0; k < 4; ++k) {
      const char c = text[i + k];
      if (c == '=') {
        if (k < 2) return false;
        ++padding;
        v[k] = 0;
        continue;
      }
      if (padding > 0) return false;  // a character after '=' in the same group
      v[k] = kBase64Values[static_cast<unsigned char>(c)];
      if (v[k] < 0) return false;
    }
    const uint32_t bits = (v[0] << 18) | (v[1] << 12) | (v[2] << 6) | v[3];
    out->push_back(static_cast<char>(bits >> 16));
    if (padding < 2) out->push_back(static_cast<char>(bits >> 8));
    if (padding < 1) out->push_back(static_cast<char>(bits));
  }
  return true;
}

GrpcWebMode GrpcWebModeOf(const std::string& media_type) {
  if (media_type == "application/grpc-web" || media_type == "application/grpc-web+proto") return GrpcWebMode::kBinary;
  if (media_type == "application/grpc-web-text" || media_type == "application/grpc-web-text+proto")
    return GrpcWebMode::kText;
  return GrpcWebMode::kNone;
}

}  // namespace armature::server::gateway
