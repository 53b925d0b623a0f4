// Test helper: a text/event-stream body split into its events.
#pragma once

#include <algorithm>
#include <string>
#include <vector>

namespace armature::testing {

struct SseEvent {
  std::string event;  // "" for message events
  std::string data;
};

inline std::vector<SseEvent> ParseSse(const std::string& text) {
  std::vector<SseEvent> events;
  SseEvent current;
  bool any = false;
  size_t start = 0;
  while (start < text.size()) {
    const size_t end = std::min(text.find('\n', start), text.size());
    const std::string line = text.substr(start, end - start);
    start = end + 1;
    if (line.empty()) {
      if (any) events.push_back(current);
      current = {};
      any = false;
    } else if (line.rfind("data: ", 0) == 0) {
      current.data += (current.data.empty() ? "" : "\n") + line.substr(6);
      any = true;
    } else if (line.rfind("event: ", 0) == 0) {
      current.event = line.substr(7);
      any = true;
    }
  }
  return events;
}

}  // namespace armature::testing
