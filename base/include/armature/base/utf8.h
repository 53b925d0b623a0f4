// UTF-8 checks and safe quoting of untrusted bytes. Names from files end up in
// protobuf strings (which must be UTF-8) and in error messages and logs
// (which JSON encoders and terminals must be able to print), so importers
// reject names that are not UTF-8 and quote input through EscapeForMessage.
#pragma once

#include <string>
#include <string_view>

namespace armature {

// True when `s` is well-formed UTF-8 (no overlongs, surrogates or code
// points above U+10FFFF).
bool IsValidUtf8(std::string_view s);

// `s` with every byte that is not part of well-formed UTF-8, every control
// character and the backslash written as \xNN, cut to `max_bytes` of input
// with "..." appended when longer. The result is always valid UTF-8.
std::string EscapeForMessage(std::string_view s, size_t max_bytes = 64);

}  // namespace armature
