// The gateway's path templates. Input: a template on the first line, request
// targets on the others. An accepted template simplifies to one that parses
// with the same variables; every target that splits is matched against it
// and against the API's real templates; a match binds each variable once, in
// order, to a value made of the target's own segments.
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include "api_bindings.h"
#include "server/host/gateway/rest/transcoding/path_template.h"

namespace {

namespace gw = armature::server::gateway;

void CheckMatch(const gw::PathTemplate& t, const gw::RequestPath& path) {
  gw::PathBindings bindings;
  if (!t.Match(path, &bindings)) return;
  const auto vars = t.variables();
  if (bindings.size() != vars.size()) std::abort();
  // The segments as matched: the verb comes off the last one.
  std::vector<std::string> segments = path.segments;
  if (!t.verb().empty()) segments.back().resize(segments.back().size() - t.verb().size() - 1);
  std::string joined = "/";
  for (const auto& s : segments) joined += s + "/";
  for (size_t i = 0; i < vars.size(); ++i) {
    if (bindings[i].first != vars[i]) std::abort();
    // A value is whole segments of the path (joined by '/'); "**" may take none.
    if (!bindings[i].second.empty() && joined.find("/" + bindings[i].second + "/") == std::string::npos) std::abort();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view in(reinterpret_cast<const char*>(data), size);
  const size_t eol = in.find('\n');
  const std::string_view text = in.substr(0, eol);
  std::string_view targets = eol == std::string_view::npos ? std::string_view() : in.substr(eol + 1);

  auto t = gw::PathTemplate::Parse(text);
  if (t.ok()) {
    auto simple = gw::PathTemplate::Parse(t->Simplified());
    if (!simple.ok() || simple->variables() != t->variables() || simple->verb() != t->verb()) std::abort();
    (void)t->specificity();
  }
  while (!targets.empty()) {
    const size_t next = targets.find('\n');
    auto path = gw::RequestPath::Parse(targets.substr(0, next));
    targets = next == std::string_view::npos ? std::string_view() : targets.substr(next + 1);
    if (!path.ok()) continue;
    if (path->segments.empty()) std::abort();
    if (t.ok()) CheckMatch(*t, *path);
    for (const auto& api : armature::fuzz::ApiBindings()) CheckMatch(api.path, *path);
  }
  return 0;
}
