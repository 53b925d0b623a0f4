// spdlog set-up: level and format (human text, or one JSON object per line).
#pragma once

#include <string>

namespace armature::server {

void ConfigureLogging(const std::string& level, const std::string& format);

}  // namespace armature::server
