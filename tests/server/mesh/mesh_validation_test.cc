// The mesh slice's own request checks: each refusal names its field.
#include <gtest/gtest.h>

#include <limits>
#include <vector>

#include "server/mesh/mesh_validation.h"

namespace armature::server {
namespace {

TEST(MeshValidation, MorphWeightsAreNoneOrOneFiniteValuePerTarget) {
  EXPECT_TRUE(ValidateWeights({}, 3, "morph_weights").ok());
  const std::vector<float> three = {0, 0.5f, 1};
  EXPECT_TRUE(ValidateWeights(three, 3, "morph_weights").ok());
  const Status count = ValidateWeights(three, 2, "morph_weights");
  EXPECT_EQ(count.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(count.message().find("morph_weights"), std::string::npos) << count.message();
  const std::vector<float> nan = {0, std::numeric_limits<float>::quiet_NaN()};
  const Status bad = ValidateWeights(nan, 2, "w");
  EXPECT_EQ(bad.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(bad.message().rfind("w", 0), 0u) << bad.message();
}

TEST(MeshValidation, ASkinRequestHasOneSource) {
  v1::SkinMeshRequest request;
  request.set_clip("walk");
  EXPECT_TRUE(ValidateSkinSource(request).ok());
  request.mutable_motion()->add_layers()->set_clip("walk");
  const Status both = ValidateSkinSource(request);
  EXPECT_EQ(both.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(both.message().find("clip"), std::string::npos) << both.message();
  EXPECT_NE(both.message().find("motion"), std::string::npos) << both.message();
}

TEST(MeshValidation, MaxInfluencesIsZeroOrOneToEight) {
  for (int ok : {0, 1, 4, 8}) EXPECT_TRUE(ValidateMaxInfluences(ok).ok()) << ok;
  for (int bad : {-1, 9, 1000}) {
    const Status st = ValidateMaxInfluences(bad);
    EXPECT_EQ(st.code(), StatusCode::kInvalidArgument) << bad;
    EXPECT_NE(st.message().find("max_influences"), std::string::npos) << st.message();
  }
}

}  // namespace
}  // namespace armature::server
