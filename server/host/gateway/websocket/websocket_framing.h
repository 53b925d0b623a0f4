// WebSocket's wire format (RFC 6455), pure (no sockets, no gRPC calls): the
// opening handshake's accept key, and frames both ways. The server reads
// masked client frames with WebSocketReader, which reassembles fragmented
// messages and bounds every size, and writes unmasked frames with
// AppendWebSocketFrame (a client passes a masking key).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace armature::server::gateway {

enum class WsOpcode : uint8_t {
  kContinuation = 0x0,
  kText = 0x1,
  kBinary = 0x2,
  kClose = 0x8,
  kPing = 0x9,
  kPong = 0xA,
};

// Close codes (RFC 6455 7.4.1); 4000 + a gRPC status code names a failed call.
inline constexpr uint16_t kWsCloseNormal = 1000;
inline constexpr uint16_t kWsCloseGoingAway = 1001;
inline constexpr uint16_t kWsCloseProtocolError = 1002;
inline constexpr uint16_t kWsCloseInvalidData = 1007;  // text that is not UTF-8
inline constexpr uint16_t kWsClosePolicy = 1008;
inline constexpr uint16_t kWsCloseTooBig = 1009;
inline constexpr uint16_t kWsCloseStatusBase = 4000;

// Sec-WebSocket-Accept for a Sec-WebSocket-Key: base64(SHA-1(key + GUID)).
std::string WebSocketAccept(std::string_view key);
// A valid Sec-WebSocket-Key is the base64 of 16 bytes (24 characters).
bool IsValidWebSocketKey(std::string_view key);

// One frame appended to `out`: FIN set unless `fin` is false, the payload
// masked with `mask` when given (clients must mask, servers must not).
void AppendWebSocketFrame(WsOpcode opcode, std::string_view payload, std::string* out, bool fin = true,
                          std::optional<uint32_t> mask = std::nullopt);
// A close frame's payload: the code big-endian, then the reason cut to fit
// 123 bytes at a UTF-8 boundary.
std::string WebSocketClosePayload(uint16_t code, std::string_view reason);

// What the reader found: a whole message (text or binary, reassembled), a
// control frame, or a protocol error to close the connection with.
struct WsEvent {
  enum class Kind { kNone, kMessage, kPing, kPong, kClose, kError };
  Kind kind = Kind::kNone;
  WsOpcode opcode = WsOpcode::kText;  // of a message
  std::string payload;                // message, ping/pong payload or close reason
  uint16_t close_code = 0;            // kClose: the peer's (1005 when absent); kError: the code to close with
};

// Incremental parser of client frames. Feed bytes as they arrive, then call
// Next until it returns kNone. Errors are final: they carry the close code
// (1002 protocol, 1007 bad UTF-8, 1009 too big) and a reason naming the fault.
class WebSocketReader {
 public:
  // `max_message_bytes` bounds a message (all its fragments together) and
  // thus the bytes buffered; `require_mask` is true on the server side.
  explicit WebSocketReader(size_t max_message_bytes, bool require_mask = true)
      : max_message_bytes_(max_message_bytes), require_mask_(require_mask) {}

  void Feed(std::string_view bytes) { buffer_.append(bytes.data(), bytes.size()); }
  WsEvent Next();
  // Bytes received but not yet consumed (a frame cut short).
  size_t buffered() const { return buffer_.size() - consumed_; }

 private:
  WsEvent Fail(uint16_t code, std::string reason);

  size_t max_message_bytes_;
  bool require_mask_;
  std::string buffer_;
  size_t consumed_ = 0;
  bool failed_ = false;
  bool in_message_ = false;  // a fragmented message is being assembled
  WsOpcode message_opcode_ = WsOpcode::kText;
  std::string message_;
};

}  // namespace armature::server::gateway
