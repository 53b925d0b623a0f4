#include "server/host/gateway/rest/json/json_string.h"

#include <cstdint>

namespace armature::server::gateway {
namespace {

constexpr char kHex[] = "0123456789abcdef";

void AppendHex16(uint32_t unit, std::string* out) {
  const char text[] = {'\\',           'u', kHex[(unit >> 12) & 15], kHex[(unit >> 8) & 15], kHex[(unit >> 4) & 15],
                       kHex[unit & 15]};
  out->append(text, sizeof text);
}

// Appends the escape of `cp` and returns true, or returns false when it is written as is.
bool AppendEscape(uint32_t cp, std::string* out) {
  switch (cp) {
    case '"': return out->append("\\\""), true;
    case '\\': return out->append("\\\\"), true;
    case '\b': return out->append("\\b"), true;
    case '\t': return out->append("\\t"), true;
    case '\n': return out->append("\\n"), true;
    case '\f': return out->append("\\f"), true;
    case '\r': return out->append("\\r"), true;
    default: break;
  }
  const bool bmp_escaped = cp < 0x20 || cp == '<' || cp == '>' || (cp >= 0x7f && cp < 0xa0) || cp == 0xad ||
                           cp == 0x6dd || cp == 0x70f || cp == 0x17b4 || cp == 0x17b5 || cp == 0xfeff ||
                           (cp >= 0xfff9 && cp <= 0xfffb) || (cp >= 0x600 && cp <= 0x603) ||
                           (cp >= 0x200b && cp <= 0x200f) || (cp >= 0x2028 && cp <= 0x202e) ||
                           (cp >= 0x2060 && cp <= 0x2064) || (cp >= 0x206a && cp <= 0x206f);
  if (bmp_escaped) return AppendHex16(cp, out), true;
  if (cp == 0xe0001 || (cp >= 0x1d173 && cp <= 0x1d17a) || (cp >= 0xe0020 && cp <= 0xe007f)) {
    AppendHex16(0xd800 + ((cp - 0x10000) >> 10), out);  // as a surrogate pair
    AppendHex16(0xdc00 + (cp & 0x3ff), out);
    return true;
  }
  return false;
}

bool NeedsNoEscape(std::string_view text) {
  for (const char c : text) {
    const auto b = static_cast<unsigned char>(c);
    if (b < 0x20 || b >= 0x7f || c == '"' || c == '<' || c == '>' || c == '\\') return false;
  }
  return true;
}

// protobuf's reading: a bad lead byte is dropped alone; a bad continuation
// byte is dropped with the bytes before it; a surrogate, a code point past
// U+10FFFF or a sequence cut short is dropped whole. Overlong forms pass.
void AppendEscaped(std::string_view text, std::string* out) {
  size_t i = 0;
  while (i < text.size()) {
    const auto lead = static_cast<unsigned char>(text[i]);
    uint32_t cp = lead;
    int more = 0;
    if (lead <= 0x7f)
      more = 0;
    else if (lead <= 0xbf) {
      ++i;
      continue;
    } else if (lead <= 0xdf)
      cp &= 0x1f, more = 1;
    else if (lead <= 0xef)
      cp &= 0x0f, more = 2;
    else if (lead <= 0xf7)
      cp &= 0x07, more = 3;
    else {
      ++i;
      continue;
    }
    size_t length = 1;
    bool valid = true;
    while (more > 0 && i + length < text.size()) {
      const auto next = static_cast<unsigned char>(text[i + length++]);
      --more;
      cp = (cp << 6) | (next & 0x3f);
      if (next < 0x80 || next > 0xbf) {
        valid = false;
        break;
      }
    }
    if (more > 0 || (cp & 0xfffff800) == 0xd800 || cp > 0x10ffff) valid = false;
    if (valid && !AppendEscape(cp, out)) out->append(text.data() + i, length);
    i += length;
  }
}

}  // namespace

void AppendJsonString(std::string_view text, std::string* out) {
  out->push_back('"');
  if (NeedsNoEscape(text))
    out->append(text);
  else
    AppendEscaped(text, out);
  out->push_back('"');
}

}  // namespace armature::server::gateway
