// WebSocket framing against the bytes of RFC 6455's own examples (1.3 for
// the accept key, 5.7 for frames) and hand-built frames for each refusal.
#include <gtest/gtest.h>

#include "server/host/gateway/websocket/websocket_framing.h"

namespace armature::server::gateway {
namespace {

using namespace std::string_literals;
using Kind = WsEvent::Kind;

TEST(WebSocketFraming, TheAcceptKeyIsRfc6455sExample) {
  EXPECT_EQ(WebSocketAccept("dGhlIHNhbXBsZSBub25jZQ=="), "s3pPLMBiTxaQ9kYGzzhZRbK+xOo=");
  EXPECT_TRUE(IsValidWebSocketKey("dGhlIHNhbXBsZSBub25jZQ=="));
  EXPECT_FALSE(IsValidWebSocketKey("dGhlIHNhbXBsZSBub25jZQ"));    // cut short
  EXPECT_FALSE(IsValidWebSocketKey("dGhlIHNhbXBsZSBub25jZSE="));  // 17 bytes
  EXPECT_FALSE(IsValidWebSocketKey("dGhlIHNhbXBsZSBub25jZ!=="));  // not base64
}

TEST(WebSocketFraming, ServerFramesAreTheRfcExamples) {
  std::string out;
  AppendWebSocketFrame(WsOpcode::kText, "Hello", &out);
  EXPECT_EQ(out, "\x81\x05Hello"s);
  out.clear();
  AppendWebSocketFrame(WsOpcode::kText, "Hel", &out, /*fin=*/false);
  AppendWebSocketFrame(WsOpcode::kContinuation, "lo", &out);
  EXPECT_EQ(out, "\x01\x03Hel\x80\x02lo"s);
  out.clear();
  AppendWebSocketFrame(WsOpcode::kPing, "Hello", &out);
  EXPECT_EQ(out, "\x89\x05Hello"s);
  out.clear();
  AppendWebSocketFrame(WsOpcode::kBinary, std::string(256, 'x'), &out);
  EXPECT_EQ(out.substr(0, 4), "\x82\x7E\x01\x00"s);
  EXPECT_EQ(out.size(), 4u + 256);
  out.clear();
  AppendWebSocketFrame(WsOpcode::kBinary, std::string(65536, 'x'), &out);
  EXPECT_EQ(out.substr(0, 10), "\x82\x7F\x00\x00\x00\x00\x00\x01\x00\x00"s);
  EXPECT_EQ(out.size(), 10u + 65536);
}

TEST(WebSocketFraming, AMaskedClientFrameIsTheRfcExample) {
  std::string out;
  AppendWebSocketFrame(WsOpcode::kText, "Hello", &out, true, 0x37fa213d);
  EXPECT_EQ(out, "\x81\x85\x37\xfa\x21\x3d\x7f\x9f\x4d\x51\x58"s);

  WebSocketReader reader(1024);
  reader.Feed(out);
  const WsEvent e = reader.Next();
  EXPECT_EQ(e.kind, Kind::kMessage);
  EXPECT_EQ(e.opcode, WsOpcode::kText);
  EXPECT_EQ(e.payload, "Hello");
  EXPECT_EQ(reader.Next().kind, Kind::kNone);
}

TEST(WebSocketFraming, FragmentsReassembleAroundAPingAndBytesMayArriveOneByOne) {
  std::string wire;
  AppendWebSocketFrame(WsOpcode::kBinary, "ab", &wire, false, 1);
  AppendWebSocketFrame(WsOpcode::kPing, "p", &wire, true, 2);
  AppendWebSocketFrame(WsOpcode::kContinuation, "cd", &wire, false, 3);
  AppendWebSocketFrame(WsOpcode::kContinuation, std::string(300, 'e'), &wire, true, 4);
  WebSocketReader reader(1024);
  std::vector<WsEvent> events;
  for (char c : wire) {
    reader.Feed(std::string_view(&c, 1));
    for (WsEvent e = reader.Next(); e.kind != Kind::kNone; e = reader.Next()) events.push_back(e);
  }
  ASSERT_EQ(events.size(), 2u);
  EXPECT_EQ(events[0].kind, Kind::kPing);
  EXPECT_EQ(events[0].payload, "p");
  EXPECT_EQ(events[1].kind, Kind::kMessage);
  EXPECT_EQ(events[1].opcode, WsOpcode::kBinary);
  EXPECT_EQ(events[1].payload, "abcd" + std::string(300, 'e'));
  EXPECT_EQ(reader.buffered(), 0u);
}

TEST(WebSocketFraming, CloseCarriesItsCodeAndReason) {
  std::string wire;
  AppendWebSocketFrame(WsOpcode::kClose, WebSocketClosePayload(1000, "bye"), &wire, true, 7);
  EXPECT_EQ(WebSocketClosePayload(1000, "bye"),
            "\x03\xE8"
            "bye"s);
  WebSocketReader reader(16);
  reader.Feed(wire);
  const WsEvent e = reader.Next();
  EXPECT_EQ(e.kind, Kind::kClose);
  EXPECT_EQ(e.close_code, 1000);
  EXPECT_EQ(e.payload, "bye");

  WebSocketReader empty(16);
  wire.clear();
  AppendWebSocketFrame(WsOpcode::kClose, "", &wire, true, 7);
  empty.Feed(wire);
  EXPECT_EQ(empty.Next().close_code, 1005);  // no code given
}

TEST(WebSocketFraming, ALongCloseReasonIsCutAtACodePointBoundary) {
  const std::string reason = std::string(120, 'a') + "\xC3\xA9\xC3\xA9";  // é é: bytes 120..123
  const std::string payload = WebSocketClosePayload(4003, reason);
  EXPECT_LE(payload.size(), 125u);
  EXPECT_EQ(payload.substr(2), std::string(120, 'a') + "\xC3\xA9");
  EXPECT_EQ(payload.substr(0, 2), "\x0F\xA3"s);  // 4003
}

// Each refusal: its close code and a reason naming the fault.
WsEvent ReadOne(const std::string& wire, size_t limit = 64, bool require_mask = true) {
  WebSocketReader reader(limit, require_mask);
  reader.Feed(wire);
  return reader.Next();
}

TEST(WebSocketFraming, MalformedFramesAreRefusedWithTheirCloseCode) {
  std::string unmasked;
  AppendWebSocketFrame(WsOpcode::kText, "x", &unmasked);
  EXPECT_EQ(ReadOne(unmasked).close_code, kWsCloseProtocolError);
  EXPECT_NE(ReadOne(unmasked).payload.find("masked"), std::string::npos);

  std::string big;
  AppendWebSocketFrame(WsOpcode::kBinary, std::string(65, 'x'), &big, true, 9);
  EXPECT_EQ(ReadOne(big).close_code, kWsCloseTooBig);
  // Refused from the header alone: a huge declared length is not waited for.
  EXPECT_EQ(ReadOne("\x82\xFF\x00\x00\x00\x01\x00\x00\x00\x00"s).close_code, kWsCloseTooBig);
  // Fragments that together exceed the limit.
  std::string parts;
  AppendWebSocketFrame(WsOpcode::kBinary, std::string(40, 'x'), &parts, false, 9);
  AppendWebSocketFrame(WsOpcode::kContinuation, std::string(40, 'x'), &parts, true, 9);
  WebSocketReader reader(64);
  reader.Feed(parts);
  EXPECT_EQ(reader.Next().close_code, kWsCloseTooBig);

  std::string bad_utf8;
  AppendWebSocketFrame(WsOpcode::kText, "\xC3\x28", &bad_utf8, true, 9);
  EXPECT_EQ(ReadOne(bad_utf8).close_code, kWsCloseInvalidData);

  std::string rsv = "\xC1\x80\x00\x00\x00\x00"s;  // RSV1 set
  EXPECT_NE(ReadOne(rsv).payload.find("reserved"), std::string::npos);
  EXPECT_NE(ReadOne("\x83\x80\x00\x00\x00\x00"s).payload.find("opcode 3"), std::string::npos);

  std::string long_ping;
  AppendWebSocketFrame(WsOpcode::kPing, std::string(126, 'p'), &long_ping, true, 9);
  EXPECT_EQ(ReadOne(long_ping, 1024).close_code, kWsCloseProtocolError);
  std::string fragmented_ping;
  AppendWebSocketFrame(WsOpcode::kPing, "p", &fragmented_ping, false, 9);
  EXPECT_NE(ReadOne(fragmented_ping).payload.find("fragmented"), std::string::npos);

  std::string stray;
  AppendWebSocketFrame(WsOpcode::kContinuation, "x", &stray, true, 9);
  EXPECT_NE(ReadOne(stray).payload.find("continuation"), std::string::npos);
  std::string interleaved;
  AppendWebSocketFrame(WsOpcode::kText, "a", &interleaved, false, 9);
  AppendWebSocketFrame(WsOpcode::kText, "b", &interleaved, true, 9);
  WebSocketReader r2(64);
  r2.Feed(interleaved);
  EXPECT_NE(r2.Next().payload.find("new message"), std::string::npos);

  std::string bad_close;
  AppendWebSocketFrame(WsOpcode::kClose, WebSocketClosePayload(1005, ""), &bad_close, true, 9);
  EXPECT_EQ(ReadOne(bad_close).kind, Kind::kError);
  EXPECT_EQ(ReadOne("\x88\x81\x00\x00\x00\x00\x03"s).kind, Kind::kError);  // 1-byte close payload

  // A client reading the server's frames refuses masked ones.
  std::string masked;
  AppendWebSocketFrame(WsOpcode::kText, "x", &masked, true, 9);
  EXPECT_EQ(ReadOne(masked, 64, /*require_mask=*/false).kind, Kind::kError);
  EXPECT_EQ(ReadOne(unmasked, 64, false).payload, "x");
}

TEST(WebSocketFraming, NothingIsReadAfterAnError) {
  std::string wire;
  AppendWebSocketFrame(WsOpcode::kText, "x", &wire);  // unmasked: an error
  AppendWebSocketFrame(WsOpcode::kText, "y", &wire, true, 9);
  WebSocketReader reader(64);
  reader.Feed(wire);
  EXPECT_EQ(reader.Next().kind, Kind::kError);
  EXPECT_EQ(reader.Next().kind, Kind::kError);
}

}  // namespace
}  // namespace armature::server::gateway
