// Enum numbers the API does not define are refused, not read as the default.
#include <string>

#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {
namespace {

TEST(EnumValidation, UnknownNumbersAreInvalidArgumentListingTheAllowedValues) {
  TempDir data;
  ServerProcess server(data.path(), {"--no-demo"});
  client::Client client(OptionsFor(server));
  client.Import({"arm.bvh", kArmBvh});
  auto evaluate = [&](auto set) {
    v1::EvaluateClipRequest r;
    r.set_clip("arm");
    r.add_times(0.5);
    set(r);
    return StatusOf([&] { client.EvaluateClip(r); });
  };
  struct Case {
    std::string field;
    grpc::Status status;
  };
  for (const Case& c : {Case{"interpolation", evaluate([](auto& r) { r.set_interpolation(v1::Interpolation(99)); })},
                        Case{"space", evaluate([](auto& r) { r.set_space(v1::Space(99)); })},
                        Case{"wrap", evaluate([](auto& r) { r.set_wrap(v1::WrapMode(99)); })}}) {
    EXPECT_EQ(c.status.error_code(), grpc::StatusCode::INVALID_ARGUMENT) << c.field;
    EXPECT_EQ(c.status.error_message().rfind(c.field + ": unknown value 99; allowed: ", 0), 0u)
        << c.status.error_message();
  }
  EXPECT_TRUE(evaluate([](auto& r) { r.set_space(v1::WORLD); }).ok());
}

}  // namespace
}  // namespace armature::testing
