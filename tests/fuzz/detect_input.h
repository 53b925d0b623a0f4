// The input of the fuzz targets that import as the server does
// (engine_detect_fuzz, engine_compress_fuzz): a first line
// "<format>/<filename>" (either may be empty), a line break, then the file.
// Without a line break the whole input is the file.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <string_view>

namespace armature::fuzz {

struct DetectInput {
  std::string_view format, filename, bytes;
};

inline DetectInput SplitDetectInput(const uint8_t* data, size_t size) {
  const std::string_view in(reinterpret_cast<const char*>(data), size);
  const size_t eol = in.find('\n');
  const std::string_view head = eol == std::string_view::npos ? std::string_view() : in.substr(0, eol);
  const size_t slash = head.find('/');
  return {head.substr(0, std::min(slash, head.size())),
          slash == std::string_view::npos ? std::string_view() : head.substr(slash + 1),
          eol == std::string_view::npos ? in : in.substr(eol + 1)};
}

}  // namespace armature::fuzz
