// Server-Sent Events: a server-streaming RPC's responses as a
// text/event-stream body, one JSON message per `data:` event, closed by one
// `event: status` carrying {"code","message","details"} (code 0 when the
// stream ended well). Comment lines keep idle streams alive and find clients
// that went away, whose call is then cancelled.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include "server/host/gateway/common/generic_call.h"

namespace httplib {
struct Response;
}

namespace armature::server::gateway {

// One event; `data` may hold newlines (each line becomes a `data:` line).
std::string SseEvent(std::string_view data, std::string_view event = {});

struct SseStream {
  std::shared_ptr<GenericCall> call;
  std::vector<std::string> already_read;                   // responses read before the stream started
  std::function<std::string(const std::string&)> to_json;  // serialized response → JSON
  std::chrono::milliseconds heartbeat{15000};
  std::function<void()> on_close;  // when the stream ends or the client goes away
};

// Makes the rest of `stream.call` the body of `res`.
void SendSse(httplib::Response& res, SseStream stream);

}  // namespace armature::server::gateway
