// One bidirectional session (IkSession, DeformSession, PlaybackSession,
// CrowdSession) on an upgraded connection, run in the HTTP handler's thread
// until it ends: one poll() over the non-blocking socket and the call's wake
// descriptor.
//
// Each text frame is one JSON request message (the first one also takes the
// path's fields), binary frames the proto encoding; answers use the encoding
// of the latest request. A failed call ends with a text frame
// {"code":…,"message":…} and a close frame with code 4000 + the gRPC code.
#pragma once

#include <chrono>
#include <string>
#include <string_view>
#include <vector>

#include <google/protobuf/message.h>
#include <grpcpp/grpcpp.h>

#include "server/host/gateway/common/bidi_call.h"
#include "server/host/gateway/common/gateway_options.h"
#include "server/host/gateway/rest/transcoding/http_rule.h"
#include "server/host/gateway/websocket/upgraded_connection.h"
#include "server/host/gateway/websocket/websocket_framing.h"

namespace armature::server::gateway {

struct WebSocketSessionParts {
  const HttpBinding* binding = nullptr;  // the bidi method's REST binding
  PathBindings variables;                // the path's fields, for the first message
  const google::protobuf::Message* request_type = nullptr;
  const google::protobuf::Message* response_type = nullptr;
};

class WebSocketSession {
 public:
  // All of them outlive the session.
  WebSocketSession(const UpgradedConnection& connection, WebSocketSessionParts parts, BidiCall& call,
                   const GatewayOptions& options);

  // Until the call ends, the client goes away or closes, or it idles too long.
  void Run();

 private:
  using Clock = std::chrono::steady_clock;
  static constexpr size_t kMaxPendingWrites = 4;

  // The call's answers as frames, as they come; false once the session is over.
  bool ForwardAnswers();
  // The client's whole frames to the call while it has room; false once the
  // session is over. `more_frames`: false when the reader has no whole frame left.
  bool ForwardRequests(bool* more_frames);
  // Waits for the socket or the call and feeds what the client sent to the
  // reader; false once the session is over.
  bool ReadClient(bool more_frames, Clock::time_point now);
  bool Feed();  // one read from the socket into the reader; false once it is closed or failed

  // One request message from a frame; INVALID_ARGUMENT naming the message.
  grpc::Status Decode(const WsEvent& event, std::string* serialized) const;
  bool Send(WsOpcode opcode, std::string_view payload) const;
  void Close(uint16_t code, std::string_view reason) const;
  // A failed session: the status as the last message, then the close.
  void Fail(const grpc::Status& status) const;

  const UpgradedConnection& connection_;
  WebSocketSessionParts parts_;
  BidiCall& call_;
  const GatewayOptions& options_;
  WebSocketReader reader_;
  std::vector<char> buf_;
  bool binary_ = false;  // the latest request's encoding, which answers follow
  bool client_closed_ = false;
  size_t received_ = 0;
  Clock::time_point idle_deadline_;
};

}  // namespace armature::server::gateway
