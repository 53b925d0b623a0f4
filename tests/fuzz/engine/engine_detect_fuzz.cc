// DetectFormat + ParseAsset as the server calls them: the first line of the
// input is "<format>/<filename>", the rest the file. Never throws, answers
// with UTF-8 messages.
#include <cstdint>
#include <cstdlib>
#include <string_view>

#include "armature/engine/io/asset.h"
#include "armature/base/utf8.h"
#include "detect_input.h"
#include "fuzz_limits.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace armature;
  const fuzz::DetectInput in = fuzz::SplitDetectInput(data, size);
  auto detected = DetectFormat(in.format, in.filename, in.bytes);
  if (!detected.ok()) {
    if (!IsValidUtf8(detected.status().message())) std::abort();
    return 0;
  }
  auto contents = ParseAsset(*detected, in.bytes, "f", {}, fuzz::Limits());
  if (!contents.ok() && !IsValidUtf8(contents.status().message())) std::abort();
  return 0;
}
