// The deform slice's own request checks: each refusal names its field.
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "server/deform/deform_validation.h"

namespace armature::server {
namespace {

TEST(DeformValidation, SetupNumbersInRange) {
  v1::DeformSetup setup;
  EXPECT_TRUE(ValidateDeformSetup(setup).ok());
  setup.set_soft(true);
  setup.set_soft_weight(-1);
  Status st = ValidateDeformSetup(setup);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message().rfind("soft_weight", 0), 0u) << st.message();
  setup.set_soft_weight(std::numeric_limits<double>::infinity());
  EXPECT_FALSE(ValidateDeformSetup(setup).ok());
  setup.set_soft_weight(2);
  EXPECT_TRUE(ValidateDeformSetup(setup).ok());
  for (int iterations : {-1, 1001}) {
    setup.set_arap_iterations(iterations);
    st = ValidateDeformSetup(setup);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << iterations;
    EXPECT_EQ(st.message().rfind("arap_iterations", 0), 0u) << st.message();
  }
}

TEST(DeformValidation, HandlePositionsAreThreeFiniteValuesEach) {
  const std::vector<double> two = {0, 1, 2, 3, 4, 5};
  EXPECT_TRUE(ValidateHandlePositions(two, 2, "positions").ok());
  Status st = ValidateHandlePositions(two, 3, "positions");
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("needs 9 values"), std::string::npos) << st.message();
  const std::vector<double> nan = {0, 1, 2, 3, std::numeric_limits<double>::quiet_NaN(), 5};
  st = ValidateHandlePositions(nan, 2, "positions");
  EXPECT_NE(st.message().find("handle 1"), std::string::npos) << st.message();
}

TEST(DeformValidation, EachHandleHasThreeCoordinates) {
  google::protobuf::RepeatedPtrField<v1::DeformHandle> handles;
  v1::DeformHandle* a = handles.Add();
  for (int c = 0; c < 3; ++c) a->add_position(c);
  EXPECT_TRUE(ValidateDeformHandles(handles).ok());
  v1::DeformHandle* b = handles.Add();
  b->add_position(1);
  const Status st = ValidateDeformHandles(handles);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("handles[1].position"), std::string::npos) << st.message();
}

}  // namespace
}  // namespace armature::server
