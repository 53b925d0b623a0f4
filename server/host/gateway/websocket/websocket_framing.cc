#include "server/host/gateway/websocket/websocket_framing.h"

#include <openssl/sha.h>

#include "armature/base/utf8.h"
#include "server/host/gateway/grpc_web/grpc_web_framing.h"  // Base64Encode, Base64Decode

namespace armature::server::gateway {
namespace {

constexpr char kGuid[] = "258EAFA5-E914-47DA-95CA-C5AB0DC85B11";
constexpr size_t kMaxControlPayload = 125;

bool IsControl(uint8_t opcode) { return (opcode & 0x8) != 0; }
bool IsKnown(uint8_t opcode) { return opcode <= 0x2 || (opcode >= 0x8 && opcode <= 0xA); }

// A close code a peer may send (RFC 6455 7.4): 1000-1003, 1007-1011, 3000-4999.
bool IsSendableCloseCode(uint16_t code) {
  return (code >= 1000 && code <= 1003) || (code >= 1007 && code <= 1011) || (code >= 3000 && code <= 4999);
}

}  // namespace

std::string WebSocketAccept(std::string_view key) {
  std::string text(key);
  text += kGuid;
  unsigned char digest[SHA_DIGEST_LENGTH];
  SHA1(reinterpret_cast<const unsigned char*>(text.data()), text.size(), digest);
  return Base64Encode(std::string_view(reinterpret_cast<const char*>(digest), sizeof(digest)));
}

bool IsValidWebSocketKey(std::string_view key) {
  std::string decoded;
  return key.size() == 24 && Base64Decode(key, &decoded) && decoded.size() == 16;
}

void AppendWebSocketFrame(WsOpcode opcode, std::string_view payload, std::string* out, bool fin,
                          std::optional<uint32_t> mask) {
  out->push_back(static_cast<char>((fin ? 0x80 : 0x00) | static_cast<uint8_t>(opcode)));
  const uint8_t mask_bit = mask ? 0x80 : 0x00;
  const uint64_t n = payload.size();
  if (n < 126) {
    out->push_back(static_cast<char>(mask_bit | n));
  } else if (n <= 0xFFFF) {
    out->push_back(static_cast<char>(mask_bit | 126));
    out->push_back(static_cast<char>(n >> 8));
    out->push_back(static_cast<char>(n & 0xFF));
  } else {
    out->push_back(static_cast<char>(mask_bit | 127));
    for (int shift = 56; shift >= 0; shift -= 8) out->push_back(static_cast<char>((n >> shift) & 0xFF));
  }
  if (!mask) {
    out->append(payload.data(), payload.size());
    return;
  }
  const uint8_t key[4] = {static_cast<uint8_t>(*mask >> 24), static_cast<uint8_t>(*mask >> 16),
                          static_cast<uint8_t>(*mask >> 8), static_cast<uint8_t>(*mask)};
  out->append(reinterpret_cast<const char*>(key), 4);
  const size_t start = out->size();
  out->append(payload.data(), payload.size());
  for (size_t i = 0; i < payload.size(); ++i) (*out)[start + i] = static_cast<char>((*out)[start + i] ^ key[i % 4]);
}

std::string WebSocketClosePayload(uint16_t code, std::string_view reason) {
  std::string out;
  out.push_back(static_cast<char>(code >> 8));
  out.push_back(static_cast<char>(code & 0xFF));
  size_t n = std::min(reason.size(), kMaxControlPayload - 2);
  // Back up to a code point's first byte so the cut keeps the reason UTF-8.
  while (n > 0 && n < reason.size() && (static_cast<uint8_t>(reason[n]) & 0xC0) == 0x80) --n;
  out.append(reason.data(), n);
  return out;
}

WsEvent WebSocketReader::Fail(uint16_t code, std::string reason) {
  failed_ = true;
  WsEvent e;
  e.kind = WsEvent::Kind::kError;
  e.close_code = code;
  e.payload = std::move(reason);
  return e;
}

WsEvent WebSocketReader::Next() {
  if (failed_) return Fail(kWsCloseProtocolError, "the connection already failed");
  while (true) {
    const auto* p = reinterpret_cast<const uint8_t*>(buffer_.data()) + consumed_;
    const size_t avail = buffer_.size() - consumed_;
    if (avail < 2) break;
    const bool fin = p[0] & 0x80;
    const uint8_t opcode = p[0] & 0x0F;
    if (p[0] & 0x70) return Fail(kWsCloseProtocolError, "frame: reserved bits set (no extension was negotiated)");
    if (!IsKnown(opcode)) return Fail(kWsCloseProtocolError, "frame: unknown opcode " + std::to_string(opcode));
    const bool masked = p[1] & 0x80;
    if (masked != require_mask_)
      return Fail(kWsCloseProtocolError,
                  require_mask_ ? "frame: client frames must be masked" : "frame: server frames must not be masked");
    uint64_t length = p[1] & 0x7F;
    size_t header = 2;
    if (length == 126) {
      if (avail < 4) break;
      length = (uint64_t{p[2]} << 8) | p[3];
      header = 4;
    } else if (length == 127) {
      if (avail < 10) break;
      length = 0;
      for (int i = 0; i < 8; ++i) length = (length << 8) | p[2 + i];
      if (length >> 63) return Fail(kWsCloseProtocolError, "frame: length has its most significant bit set");
      header = 10;
    }
    if (IsControl(opcode)) {
      if (!fin) return Fail(kWsCloseProtocolError, "frame: a control frame cannot be fragmented");
      if (length > kMaxControlPayload)
        return Fail(kWsCloseProtocolError, "frame: a control frame carries at most 125 bytes");
    } else {
      const size_t so_far = in_message_ ? message_.size() : 0;
      if (length > max_message_bytes_ || so_far + length > max_message_bytes_)
        return Fail(kWsCloseTooBig, "message: more than " + std::to_string(max_message_bytes_) + " bytes");
      if (opcode == 0 && !in_message_) return Fail(kWsCloseProtocolError, "frame: continuation without a message");
      if (opcode != 0 && in_message_)
        return Fail(kWsCloseProtocolError, "frame: a new message began before the fragmented one ended");
    }
    if (masked) header += 4;
    if (avail < header || avail - header < length) break;

    std::string payload(reinterpret_cast<const char*>(p + header), static_cast<size_t>(length));
    if (masked) {
      const uint8_t* key = p + header - 4;
      for (size_t i = 0; i < payload.size(); ++i) payload[i] = static_cast<char>(payload[i] ^ key[i % 4]);
    }
    consumed_ += header + static_cast<size_t>(length);
    if (consumed_ == buffer_.size() || consumed_ > (64u << 10)) {  // keep the buffer from growing
      buffer_.erase(0, consumed_);
      consumed_ = 0;
    }

    WsEvent e;
    switch (static_cast<WsOpcode>(opcode)) {
      case WsOpcode::kPing:
        e.kind = WsEvent::Kind::kPing;
        e.payload = std::move(payload);
        return e;
      case WsOpcode::kPong:
        e.kind = WsEvent::Kind::kPong;
        e.payload = std::move(payload);
        return e;
      case WsOpcode::kClose:
        e.kind = WsEvent::Kind::kClose;
        if (payload.size() == 1) return Fail(kWsCloseProtocolError, "close frame: a 1-byte payload");
        e.close_code = 1005;
        if (payload.size() >= 2) {
          e.close_code =
              static_cast<uint16_t>((static_cast<uint8_t>(payload[0]) << 8) | static_cast<uint8_t>(payload[1]));
          if (!IsSendableCloseCode(e.close_code))
            return Fail(kWsCloseProtocolError, "close frame: code " + std::to_string(e.close_code) + " is not allowed");
          e.payload = payload.substr(2);
          if (!IsValidUtf8(e.payload)) return Fail(kWsCloseInvalidData, "close frame: the reason is not UTF-8");
        }
        failed_ = true;  // nothing follows a close
        return e;
      default: break;
    }
    if (opcode != 0) {
      in_message_ = true;
      message_opcode_ = static_cast<WsOpcode>(opcode);
      message_.clear();
    }
    message_ += payload;
    if (!fin) continue;
    in_message_ = false;
    if (message_opcode_ == WsOpcode::kText && !IsValidUtf8(message_))
      return Fail(kWsCloseInvalidData, "text message: not valid UTF-8");
    e.kind = WsEvent::Kind::kMessage;
    e.opcode = message_opcode_;
    e.payload = std::move(message_);
    message_.clear();
    return e;
  }
  return WsEvent{};
}

}  // namespace armature::server::gateway
