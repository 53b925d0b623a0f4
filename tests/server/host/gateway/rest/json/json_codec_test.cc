// JSON → request message: enum names in any case; a bad enum name lists the allowed ones.
#include "server/host/gateway/rest/json/json_codec.h"

#include <gtest/gtest.h>

#include "armature/v1/poses.pb.h"

namespace armature::server::gateway {
namespace {

TEST(JsonCodec, EnumNamesAreAcceptedInAnyCase) {
  for (const char* spelling : {"WORLD", "world", "World"}) {
    v1::EvaluateClipRequest request;
    const grpc::Status st =
        JsonToMessage(std::string(R"({"space":")") + spelling + "\"}", &request, "request body", "request body field");
    ASSERT_TRUE(st.ok()) << spelling << ": " << st.error_message();
    EXPECT_EQ(request.space(), v1::WORLD) << spelling;
  }
}

TEST(JsonCodec, AnUnknownEnumNameListsTheAllowedValues) {
  v1::EvaluateClipRequest request;
  const grpc::Status st = JsonToMessage(R"({"space":"sky"})", &request, "request body", "request body field");
  EXPECT_EQ(st.error_code(), grpc::StatusCode::INVALID_ARGUMENT);
  EXPECT_EQ(st.error_message(),
            "request body field 'space': invalid value \"sky\" for type type.googleapis.com/armature.v1.Space; "
            "allowed: SPACE_UNSPECIFIED, LOCAL, WORLD (any case)");
}

}  // namespace
}  // namespace armature::server::gateway
