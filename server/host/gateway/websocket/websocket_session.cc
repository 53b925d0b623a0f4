#include "server/host/gateway/websocket/websocket_session.h"

#include <poll.h>

#include <algorithm>
#include <cerrno>
#include <memory>

#include "server/host/gateway/common/error_mapping.h"
#include "server/host/gateway/rest/json/json_codec.h"
#include "server/host/gateway/rest/transcoding/transcoder.h"

namespace armature::server::gateway {

namespace pb = google::protobuf;

WebSocketSession::WebSocketSession(const UpgradedConnection& connection, WebSocketSessionParts parts, BidiCall& call,
                                   const GatewayOptions& options)
    : connection_(connection),
      parts_(std::move(parts)),
      call_(call),
      options_(options),
      reader_(options.max_request_bytes),
      buf_(64 << 10),
      idle_deadline_(Clock::now() + options.websocket_idle_timeout) {}

void WebSocketSession::Run() {
  while (true) {
    if (!ForwardAnswers()) return;
    bool more_frames = true;
    if (!ForwardRequests(&more_frames)) return;
    const auto now = Clock::now();
    if (now >= idle_deadline_) {
      call_.Cancel();
      return Close(kWsCloseGoingAway, "idle for " + std::to_string(options_.websocket_idle_timeout.count()) + " ms");
    }
    if (!ReadClient(more_frames, now)) return;
  }
}

bool WebSocketSession::ForwardAnswers() {
  std::string answer;
  BidiCall::Next next;
  while ((next = call_.Read(&answer)) == BidiCall::Next::kMessage) {
    bool sent;
    if (binary_) {
      sent = Send(WsOpcode::kBinary, answer);
    } else {
      HttpBody body;
      const grpc::Status st =
          TranscodeResponse(*parts_.binding, *parts_.response_type, std::move(answer), options_.max_reply_bytes, &body);
      if (!st.ok()) {
        Fail(st);
        return false;
      }
      sent = Send(WsOpcode::kText, body.content);
    }
    if (!sent) return false;
  }
  if (next != BidiCall::Next::kEnd) return true;
  const grpc::Status status = call_.status();
  if (!status.ok())
    Fail(status);
  else
    Close(kWsCloseNormal, "");
  return false;
}

bool WebSocketSession::ForwardRequests(bool* more_frames) {
  while (!client_closed_ && call_.pending_writes() < kMaxPendingWrites) {
    WsEvent e = reader_.Next();
    switch (e.kind) {
      case WsEvent::Kind::kNone: *more_frames = false; return true;
      case WsEvent::Kind::kMessage: {
        ++received_;
        idle_deadline_ = Clock::now() + options_.websocket_idle_timeout;
        binary_ = e.opcode == WsOpcode::kBinary;
        std::string serialized;
        if (auto st = Decode(e, &serialized); !st.ok()) {
          Fail(st);
          return false;
        }
        (void)call_.Write(std::move(serialized));  // refused once the call ended: its status follows
        break;
      }
      case WsEvent::Kind::kPing:
        if (!Send(WsOpcode::kPong, e.payload)) return false;
        break;
      case WsEvent::Kind::kPong: break;
      case WsEvent::Kind::kClose:
        // The client is done sending: half-close, answer what is left, then close.
        client_closed_ = true;
        call_.WritesDone();
        idle_deadline_ = std::min(idle_deadline_, Clock::now() + std::chrono::seconds(5));
        break;
      case WsEvent::Kind::kError: Close(e.close_code, e.payload); return false;
    }
  }
  return true;
}

bool WebSocketSession::ReadClient(bool more_frames, Clock::time_point now) {
  // Read from the socket only when the reader has no whole frame left.
  const bool want_socket = !client_closed_ && !more_frames && call_.pending_writes() < kMaxPendingWrites;
  if (want_socket && connection_.Buffered()) return Feed();
  pollfd fds[2] = {{call_.wake_fd(), POLLIN, 0}, {connection_.fd(), static_cast<short>(want_socket ? POLLIN : 0), 0}};
  const auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(idle_deadline_ - now).count() + 1;
  if (::poll(fds, 2, static_cast<int>(std::min<int64_t>(wait, 60000))) < 0 && errno != EINTR) return false;
  if (fds[0].revents) call_.ClearWake();
  if (fds[1].revents & (POLLERR | POLLNVAL)) return false;
  if (fds[1].revents & (POLLIN | POLLHUP)) return Feed();
  return true;
}

bool WebSocketSession::Feed() {
  const ssize_t n = connection_.Read(buf_.data(), buf_.size());
  if (n == UpgradedConnection::kNothingYet) return true;  // part of a TLS record: the rest comes later
  if (n <= 0) return false;                               // the client went away: the call is cancelled
  reader_.Feed(std::string_view(buf_.data(), static_cast<size_t>(n)));
  return true;
}

grpc::Status WebSocketSession::Decode(const WsEvent& e, std::string* serialized) const {
  const std::string where = "message " + std::to_string(received_);
  std::unique_ptr<pb::Message> m(parts_.request_type->New());
  if (e.opcode == WsOpcode::kBinary) {
    if (!m->ParseFromString(e.payload))
      return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                          where + ": not a valid " + parts_.request_type->GetTypeName() + " encoding");
  } else if (auto st = JsonToMessage(e.payload, m.get(), where, where + " field"); !st.ok()) {
    return st;
  }
  if (received_ == 1) {  // the path's fields go with the first message
    HttpRequestParts http;
    http.path = parts_.variables;
    std::unique_ptr<pb::Message> params(parts_.request_type->New());
    if (auto st = ParamsMessage(*parts_.binding, http, params.get()); !st.ok()) return st;
    m->MergeFrom(*params);
  }
  *serialized = m->SerializeAsString();
  return grpc::Status::OK;
}

bool WebSocketSession::Send(WsOpcode opcode, std::string_view payload) const {
  std::string frame;
  AppendWebSocketFrame(opcode, payload, &frame);
  return connection_.Write(frame);
}

void WebSocketSession::Close(uint16_t code, std::string_view reason) const {
  (void)Send(WsOpcode::kClose, WebSocketClosePayload(code, reason));
}

void WebSocketSession::Fail(const grpc::Status& status) const {
  if (Send(WsOpcode::kText, ErrorJson(status.error_code(), status.error_message())))
    Close(static_cast<uint16_t>(kWsCloseStatusBase + status.error_code()), status.error_message());
}

}  // namespace armature::server::gateway
