#include "server/host/gateway/rest/sse.h"

#include <httplib.h>

#include "server/host/gateway/common/error_mapping.h"

namespace armature::server::gateway {

std::string SseEvent(std::string_view data, std::string_view event) {
  std::string out;
  if (!event.empty()) out.append("event: ").append(event).append("\n");
  size_t start = 0;
  while (true) {
    const size_t end = data.find('\n', start);
    out.append("data: ").append(data.substr(start, end == std::string_view::npos ? end : end - start)).append("\n");
    if (end == std::string_view::npos) break;
    start = end + 1;
  }
  return out + "\n";
}

void SendSse(httplib::Response& res, SseStream stream) {
  res.status = 200;
  res.set_header("Cache-Control", "no-cache");
  res.set_header("X-Accel-Buffering", "no");  // proxies must not buffer the stream
  struct State : SseStream {
    bool closed = false;
  };
  auto state = std::make_shared<State>(State{std::move(stream)});
  res.set_chunked_content_provider(
      "text/event-stream",
      [state](size_t, httplib::DataSink& sink) -> bool {
        // Each call writes at least one thing, so a vanished client shows up
        // as a failed write within one heartbeat.
        if (!state->already_read.empty()) {
          std::string events;
          for (const auto& m : state->already_read) events += SseEvent(state->to_json(m));
          state->already_read.clear();
          return sink.write(events.data(), events.size());
        }
        std::string message;
        switch (state->call->Read(&message, state->heartbeat)) {
          case GenericCall::Next::kMessage: {
            const std::string event = SseEvent(state->to_json(message));
            return sink.write(event.data(), event.size());
          }
          case GenericCall::Next::kTimeout: {
            static constexpr std::string_view kKeepAlive = ": keep-alive\n\n";
            return sink.write(kKeepAlive.data(), kKeepAlive.size());
          }
          case GenericCall::Next::kEnd: {
            const grpc::Status status = state->call->status();
            const std::string event = SseEvent(ErrorJson(status.error_code(), status.error_message()), "status");
            if (!sink.write(event.data(), event.size())) return false;
            sink.done();
            return true;
          }
        }
        return false;
      },
      [state](bool) {
        if (state->closed) return;
        state->closed = true;
        state->call->Cancel();  // no-op when it already ended
        if (state->on_close) state->on_close();
      });
}

}  // namespace armature::server::gateway
