// LogFields (the request log's cheap path) writes the same text line as
// LogEvent over a JSON object of the same fields.
#include <gtest/gtest.h>

#include <sstream>

#include <spdlog/sinks/ostream_sink.h>
#include <spdlog/spdlog.h>

#include "server/host/observability/logging.h"

namespace armature::server {
namespace {

class LoggingText : public ::testing::Test {
 protected:
  void SetUp() override {
    previous_ = spdlog::default_logger();
    auto sink = std::make_shared<spdlog::sinks::ostream_sink_mt>(out_);
    auto logger = std::make_shared<spdlog::logger>("logging_test", sink);
    logger->set_pattern("%v");
    logger->set_level(spdlog::level::info);
    spdlog::set_default_logger(logger);
  }
  void TearDown() override { spdlog::set_default_logger(previous_); }
  std::string Take() {
    std::string s = out_.str();
    out_.str("");
    return s;
  }

  std::ostringstream out_;
  std::shared_ptr<spdlog::logger> previous_;
};

TEST_F(LoggingText, FieldsWriteTheLineLogEventWrites) {
  const std::string error = "clip 'a b' not \"found\"";
  const LogField fields[] = {{"code", std::string_view("NOT_FOUND")},
                             {"duration_ms", 0.125},
                             {"error", std::string_view(error)},
                             {"method", std::string_view("armature.v1.PoseService/EvaluateClip")},
                             {"whole", 2.0}};
  LogFields(spdlog::level::info, "rpc", fields);
  const std::string fast = Take();
  LogEvent(spdlog::level::info, "rpc",
           {{"code", "NOT_FOUND"},
            {"duration_ms", 0.125},
            {"error", error},
            {"method", "armature.v1.PoseService/EvaluateClip"},
            {"whole", 2.0}});
  EXPECT_EQ(fast, Take());
  // Written out by hand: bare words stay bare, a string with a space or quote is JSON-quoted.
  EXPECT_EQ(fast,
            "rpc code=NOT_FOUND duration_ms=0.125 error=\"clip 'a b' not \\\"found\\\"\" "
            "method=armature.v1.PoseService/EvaluateClip whole=2.0\n");
}

TEST_F(LoggingText, BelowTheLevelNothingIsWritten) {
  const LogField fields[] = {{"code", std::string_view("OK")}};
  LogFields(spdlog::level::debug, "rpc", fields);
  EXPECT_EQ(Take(), "");
}

}  // namespace
}  // namespace armature::server
