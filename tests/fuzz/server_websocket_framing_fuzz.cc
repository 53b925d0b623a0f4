// WebSocket framing (server/host/gateway/websocket/websocket_framing): the client frame
// reader. Input: a byte choosing the message size limit and the split points,
// then bytes off the wire. Whatever the split, the reader finds the same
// events; no message exceeds the limit, text is UTF-8, a close code is one a
// peer may send, nothing follows an error or a close, and an accepted message
// re-framed by the client writer reads back the same.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "armature/base/utf8.h"
#include "server/host/gateway/websocket/websocket_framing.h"

namespace gw = armature::server::gateway;

namespace {

std::vector<gw::WsEvent> ReadAll(std::string_view wire, size_t limit, size_t step) {
  gw::WebSocketReader reader(limit);
  std::vector<gw::WsEvent> events;
  for (size_t at = 0; at < wire.size(); at += step) {
    reader.Feed(wire.substr(at, step));
    for (gw::WsEvent e = reader.Next(); e.kind != gw::WsEvent::Kind::kNone; e = reader.Next()) {
      events.push_back(e);
      if (e.kind == gw::WsEvent::Kind::kError || e.kind == gw::WsEvent::Kind::kClose) return events;
    }
  }
  return events;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size == 0) return 0;
  const size_t limit = size_t{1} << (data[0] % 20);
  const size_t step = 1 + (data[0] >> 5);
  const std::string_view wire(reinterpret_cast<const char*>(data) + 1, size - 1);

  const auto whole = ReadAll(wire, limit, wire.size() + 1);
  const auto split = ReadAll(wire, limit, step);
  if (whole.size() != split.size()) std::abort();
  for (size_t i = 0; i < whole.size(); ++i) {
    const gw::WsEvent& e = whole[i];
    if (e.kind != split[i].kind || e.payload != split[i].payload || e.close_code != split[i].close_code) std::abort();
    switch (e.kind) {
      case gw::WsEvent::Kind::kMessage: {
        if (e.payload.size() > limit) std::abort();
        if (e.opcode == gw::WsOpcode::kText && !armature::IsValidUtf8(e.payload)) std::abort();
        std::string again;
        gw::AppendWebSocketFrame(e.opcode, e.payload, &again, true, 0x01020304);
        const auto back = ReadAll(again, limit, again.size() + 1);
        if (back.size() != 1 || back[0].payload != e.payload || back[0].opcode != e.opcode) std::abort();
        break;
      }
      case gw::WsEvent::Kind::kPing:
      case gw::WsEvent::Kind::kPong:
        if (e.payload.size() > 125) std::abort();
        break;
      case gw::WsEvent::Kind::kClose:
        if (e.close_code != 1005 && (e.close_code < 1000 || e.close_code > 4999)) std::abort();
        if (!armature::IsValidUtf8(e.payload)) std::abort();
        break;
      case gw::WsEvent::Kind::kError:
        if (e.payload.empty() || (e.close_code != 1002 && e.close_code != 1007 && e.close_code != 1009)) std::abort();
        break;
      case gw::WsEvent::Kind::kNone: std::abort();
    }
  }
  // A close payload always fits a control frame and keeps its reason UTF-8.
  const std::string reason = armature::EscapeForMessage(wire, 400);
  const std::string close = gw::WebSocketClosePayload(4003, reason);
  if (close.size() > 125 || !armature::IsValidUtf8(close.substr(2))) std::abort();
  return 0;
}
