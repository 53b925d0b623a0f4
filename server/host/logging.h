// spdlog set-up: level and format (human text, or one JSON object per line).
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>
#include <spdlog/common.h>

namespace armature::server {

void ConfigureLogging(const std::string& level, const std::string& format);

// One log line with structured fields: in JSON format they become keys of
// the line's object, in text format " key=value" after the message.
void LogEvent(spdlog::level::level_enum level, std::string_view message, const nlohmann::json& fields);

}  // namespace armature::server
