// UTF-8 checks for text quoted from input into messages and logs.
#pragma once

#include <string>
#include <string_view>

namespace armature {

// Whether `text` is well-formed UTF-8 (no overlongs, surrogates or code points past U+10FFFF).
bool IsValidUtf8(std::string_view text);

// `text` with every byte that is not part of a well-formed UTF-8 sequence
// written as \xNN, so the result is always valid UTF-8.
std::string EscapeForMessage(std::string_view text);

}  // namespace armature
