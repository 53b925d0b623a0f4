// DetectFormat + ParseAsset as the server calls them: the first line of the
// input is "<format>/<filename>", the rest the file. Never throws, answers
// with UTF-8 messages.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "armature/engine/io/asset.h"
#include "armature/base/utf8.h"
#include "fuzz_limits.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace armature;
  std::string_view in(reinterpret_cast<const char*>(data), size);
  const size_t eol = in.find('\n');
  const std::string_view head = eol == std::string_view::npos ? std::string_view() : in.substr(0, eol);
  const std::string_view bytes = eol == std::string_view::npos ? in : in.substr(eol + 1);
  const size_t slash = head.find('/');
  const std::string_view format = head.substr(0, std::min(slash, head.size()));
  const std::string_view filename = slash == std::string_view::npos ? std::string_view() : head.substr(slash + 1);
  auto detected = DetectFormat(format, filename, bytes);
  if (!detected.ok()) {
    if (!IsValidUtf8(detected.status().message())) std::abort();
    return 0;
  }
  auto contents = ParseAsset(*detected, bytes, "f", {}, fuzz::Limits());
  if (!contents.ok() && !IsValidUtf8(contents.status().message())) std::abort();
  return 0;
}
