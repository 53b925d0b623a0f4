// A JSON string as protobuf's JSON printer (3.21, util/internal/json_escaping)
// writes it, quotes included: '"', '\' and control characters escaped, and
// also '<', '>', U+007F–U+009F and the invisible code points it lists
// (\u00ad, \u2028, …) as \uXXXX; bytes that are not UTF-8 are dropped.
#pragma once

#include <string>
#include <string_view>

namespace armature::server::gateway {

void AppendJsonString(std::string_view text, std::string* out);

}  // namespace armature::server::gateway
