#include "server/host/observability/logging.h"

#include <chrono>

#include <spdlog/pattern_formatter.h>
#include <spdlog/sinks/stdout_color_sinks.h>
#include <spdlog/spdlog.h>

namespace armature::server {
namespace {

bool g_json = false;
// The fields of the LogEvent being formatted on this thread (spdlog's
// default logger formats synchronously, on the logging thread).
thread_local const nlohmann::json* t_fields = nullptr;

// One JSON object per line: {"ts":…,"level":…,"msg":…, fields…}. nlohmann escapes the message.
class JsonFormatter final : public spdlog::formatter {
 public:
  void format(const spdlog::details::log_msg& msg, spdlog::memory_buf_t& dest) override {
    const auto ms = std::chrono::duration_cast<std::chrono::milliseconds>(msg.time.time_since_epoch()).count();
    nlohmann::json j = {{"ts_ms", ms},
                        {"level", spdlog::level::to_string_view(msg.level).data()},
                        {"msg", std::string(msg.payload.data(), msg.payload.size())}};
    if (msg.logger_name.size() > 0) j["logger"] = std::string(msg.logger_name.data(), msg.logger_name.size());
    if (t_fields != nullptr && t_fields->is_object())
      for (const auto& [key, value] : t_fields->items())
        if (!j.contains(key)) j[key] = value;
    const std::string line = j.dump(-1, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
    dest.append(line.data(), line.data() + line.size());
  }
  std::unique_ptr<spdlog::formatter> clone() const override { return std::make_unique<JsonFormatter>(); }
};

// " key=value" of the text format for a string value. Strings with spaces
// (error messages) are quoted, so a line still splits into key=value pairs.
void AppendTextField(std::string& line, std::string_view key, std::string_view value) {
  line += ' ';
  line.append(key);
  line += '=';
  if (value.find_first_of(" =\"") == std::string_view::npos)
    line.append(value);
  else
    line += nlohmann::json(value).dump(-1, ' ', false, nlohmann::json::error_handler_t::replace);  // never throws
}

// " key=value" for any other value: its JSON text as it is.
void AppendTextDump(std::string& line, std::string_view key, const std::string& dump) {
  line += ' ';
  line.append(key);
  line += '=';
  line += dump;
}

}  // namespace

void ConfigureLogging(const std::string& level, const std::string& format) {
  auto logger = spdlog::stderr_color_mt("armature");
  spdlog::set_default_logger(logger);
  spdlog::set_level(spdlog::level::from_str(level));
  g_json = format == "json";
  if (g_json) {
    spdlog::set_formatter(std::make_unique<JsonFormatter>());
  } else {
    spdlog::set_pattern("%Y-%m-%dT%H:%M:%S.%e %^%l%$ %v");
  }
  spdlog::flush_on(spdlog::level::info);
}

void LogEvent(spdlog::level::level_enum level, std::string_view message, const nlohmann::json& fields) {
  if (!spdlog::should_log(level)) return;
  if (g_json) {
    t_fields = &fields;
    spdlog::log(level, "{}", message);
    t_fields = nullptr;
    return;
  }
  std::string line(message);
  for (const auto& [key, value] : fields.items()) {
    if (value.is_string())
      AppendTextField(line, key, value.get_ref<const std::string&>());
    else
      AppendTextDump(line, key, value.dump());
  }
  spdlog::log(level, "{}", line);
}

void LogFields(spdlog::level::level_enum level, std::string_view message, std::span<const LogField> fields) {
  if (!spdlog::should_log(level)) return;
  if (g_json) {
    nlohmann::json object = nlohmann::json::object();
    for (const LogField& f : fields) std::visit([&](const auto& v) { object[std::string(f.key)] = v; }, f.value);
    return LogEvent(level, message, object);
  }
  std::string line;
  line.reserve(256);
  line.append(message);
  for (const LogField& f : fields) {
    if (const auto* text = std::get_if<std::string_view>(&f.value))
      AppendTextField(line, f.key, *text);
    else
      AppendTextDump(line, f.key, nlohmann::json(std::get<double>(f.value)).dump());  // LogEvent's number format
  }
  spdlog::log(level, "{}", line);
}

}  // namespace armature::server
