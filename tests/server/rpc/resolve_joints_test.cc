// Unknown joint names: a close match is suggested and the skeleton's joints are listed.
#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "armature/base/closest_name.h"
#include "server/rpc/request_validation.h"

namespace armature::server {
namespace {

TEST(ResolveJoints, AnUnknownJointSuggestsTheClosestAndListsTheJoints) {
  auto catalog = test_util::DemoCatalog();
  const Skeleton& skeleton = *catalog->FindClip("demo_walk")->part->runtime->skeleton;
  google::protobuf::RepeatedPtrField<std::string> names;
  names.Add("Hips");
  names.Add("LeftWirst");
  auto joints = ResolveJoints(skeleton, names, "joints");
  ASSERT_FALSE(joints.ok());
  EXPECT_EQ(joints.status().code(), StatusCode::kNotFound);
  const std::string message = joints.status().message();
  EXPECT_EQ(message.rfind("joints[1]: unknown joint 'LeftWirst'; did you mean 'LeftWrist'? (the skeleton's 19 joints: "
                          "Hips, ",
                          0),
            0u)
      << message;
  for (const std::string& joint : skeleton.names) EXPECT_NE(message.find(joint), std::string::npos) << joint;
}

TEST(ClosestName, SuggestsOnlyWhatIsCloseEnoughToBeATypo) {
  const std::vector<std::string_view> names = {"demo_walk", "demo_character.walk", "LeftWrist"};
  EXPECT_EQ(ClosestName("demo_wlak", names), "demo_walk");
  EXPECT_EQ(ClosestName("DEMO_WALK", names), "demo_walk");  // case is ignored
  EXPECT_EQ(ClosestName("demo_character.wak", names), "demo_character.walk");
  EXPECT_EQ(ClosestName("nope", names), "");
  EXPECT_EQ(ClosestName("xy", {"ab"}), "");  // every letter differs: not a typo
  EXPECT_EQ(ClosestName(std::string(1000, 'a'), names), "");
  EXPECT_EQ(JoinNames({"a", "b", "c"}, 2), "a, b, … (1 more)");
}

TEST(ClosestName, AJointTypedWithoutItsNamespaceFindsIt) {
  const std::vector<std::string> mixamo = {"mixamorig:Hips", "mixamorig:LeftHand", "mixamorig:LeftHandIndex1",
                                           "mixamorig:RightHand"};
  const std::vector<std::string_view> names(mixamo.begin(), mixamo.end());
  EXPECT_EQ(ClosestName("LeftHand", names), "mixamorig:LeftHand");
  EXPECT_EQ(ClosestName("lefthnd", names), "mixamorig:LeftHand");
  EXPECT_EQ(ClosestName("mixamorig:LeftHnd", names), "mixamorig:LeftHand");
  EXPECT_EQ(ClosestName("Spine", names), "");
  EXPECT_EQ(ClosestName("Hips", {"rig|Hips", "rig|Head"}), "rig|Hips");
  EXPECT_NE(UnknownJoint("LeftHand", mixamo).find("did you mean 'mixamorig:LeftHand'?"), std::string::npos)
      << UnknownJoint("LeftHand", mixamo);
}

}  // namespace
}  // namespace armature::server
