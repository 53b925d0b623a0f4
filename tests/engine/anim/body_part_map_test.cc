// Retargeting's automatic joint map (anim/body_part_map.h): names read as
// body parts across naming schemes (CMU, RobotExpressive, the demo
// character, mixamo, Character Creator), explicit pairs overriding it, and
// bad explicit pairs named.
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/body_part_map.h"
#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/demo_walk.h"
#include "armature/engine/io/gltf/gltf.h"

namespace armature {
namespace {

// name → parent name ("" for the root), parents first.
std::shared_ptr<Skeleton> Tree(const std::vector<std::pair<std::string, std::string>>& joints) {
  auto s = std::make_shared<Skeleton>();
  for (const auto& [name, parent] : joints) {
    s->names.push_back(name);
    s->parents.push_back(parent.empty() ? -1 : s->Find(parent));
    Trs rest;
    rest.translation = Eigen::Vector3d(0, 1, 0);
    s->rest.push_back(rest);
  }
  s->channels.resize(s->size());
  s->end_sites.resize(s->size());
  EXPECT_TRUE(s->Validate().ok());
  return s;
}

// target joint name → source joint name
std::map<std::string, std::string> Pairs(const Skeleton& source, const Skeleton& target, const BodyPartMap& map) {
  std::map<std::string, std::string> out;
  for (const JointPairIndex& p : map.pairs)
    out[target.names[static_cast<size_t>(p.target)]] = source.names[static_cast<size_t>(p.source)];
  return out;
}

std::shared_ptr<const Skeleton> LoadShared(const std::string& relative) {
  std::ifstream in(std::string(ARMATURE_SHARED_DATA) + "/" + relative, std::ios::binary);
  if (!in) return nullptr;
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  if (relative.ends_with(".bvh")) {
    auto bvh = ParseBvh(bytes);
    EXPECT_TRUE(bvh.ok()) << bvh.status().message();
    return bvh.ok() ? bvh->clip->skeleton : nullptr;
  }
  auto asset = ParseGltf(bytes, relative.ends_with(".glb"), "x");
  EXPECT_TRUE(asset.ok()) << asset.status().message();
  return asset.ok() ? asset->skeletons.at(0).skeleton : nullptr;
}

TEST(BodyPartMap, NormalizesPrefixesSeparatorsSidesAndNumbers) {
  struct Case {
    const char* name;
    BodySide side;
    const char* base;
    int number;
    bool tip;
  };
  const Case cases[] = {
      {"mixamorig:LeftUpLeg", BodySide::kLeft, "upleg", -1, false},
      {"mixamorig_RightForeArm", BodySide::kRight, "forearm", -1, false},
      {"CC_Base_L_Thigh", BodySide::kLeft, "thigh", -1, false},
      {"UpperLegL", BodySide::kLeft, "upperleg", -1, false},
      {"thigh.R", BodySide::kRight, "thigh", -1, false},
      {"upperarm_l", BodySide::kLeft, "upperarm", -1, false},
      {"LHipJoint", BodySide::kLeft, "hipjoint", -1, false},
      {"Bip01 R Calf", BodySide::kRight, "calf", -1, false},
      {"Spine1", BodySide::kCenter, "spine", 1, false},
      {"CC_Base_Spine02", BodySide::kCenter, "spine", 2, false},
      {"Torso_1", BodySide::kCenter, "torso", 1, false},
      {"Head_end", BodySide::kCenter, "head", -1, true},
      {"Palm2L", BodySide::kLeft, "palm", 2, false},
      {"lefthand", BodySide::kLeft, "hand", -1, false},
  };
  for (const Case& c : cases) {
    const JointNameKey key = NormalizeJointName(c.name);
    EXPECT_EQ(key.side, c.side) << c.name;
    EXPECT_EQ(key.base, c.base) << c.name;
    EXPECT_EQ(key.number, c.number) << c.name;
    EXPECT_EQ(key.tip, c.tip) << c.name;
  }
}

// Three joints per finger under each hand, named by `name(side, finger, k)`.
void AddFingers(std::vector<std::pair<std::string, std::string>>& j, const std::string& hand_of_side_left,
                const std::string& hand_of_side_right, const std::vector<std::string>& fingers,
                const std::function<std::string(bool left, const std::string& finger, int k)>& name) {
  for (bool left : {true, false})
    for (const std::string& f : fingers)
      for (int k = 1; k <= 3; ++k)
        j.push_back(
            {name(left, f, k), k == 1 ? (left ? hand_of_side_left : hand_of_side_right) : name(left, f, k - 1)});
}

std::shared_ptr<Skeleton> Mixamo(bool fingers = false) {
  std::vector<std::pair<std::string, std::string>> j = {{"mixamorig:Hips", ""},
                                                        {"mixamorig:Spine", "mixamorig:Hips"},
                                                        {"mixamorig:Spine1", "mixamorig:Spine"},
                                                        {"mixamorig:Spine2", "mixamorig:Spine1"},
                                                        {"mixamorig:Neck", "mixamorig:Spine2"},
                                                        {"mixamorig:Head", "mixamorig:Neck"},
                                                        {"mixamorig:HeadTop_End", "mixamorig:Head"}};
  for (std::string s : {"Left", "Right"}) {
    const std::string m = "mixamorig:" + s;
    j.insert(j.end(), {{m + "Shoulder", "mixamorig:Spine2"},
                       {m + "Arm", m + "Shoulder"},
                       {m + "ForeArm", m + "Arm"},
                       {m + "Hand", m + "ForeArm"},
                       {m + "UpLeg", "mixamorig:Hips"},
                       {m + "Leg", m + "UpLeg"},
                       {m + "Foot", m + "Leg"},
                       {m + "ToeBase", m + "Foot"}});
  }
  if (fingers)
    AddFingers(j, "mixamorig:LeftHand", "mixamorig:RightHand", {"Thumb", "Index", "Middle", "Ring", "Pinky"},
               [](bool left, const std::string& f, int k) {
                 return std::string("mixamorig:") + (left ? "Left" : "Right") + "Hand" + f + std::to_string(k);
               });
  return Tree(j);
}

std::shared_ptr<Skeleton> CharacterCreator(bool fingers = false) {
  std::vector<std::pair<std::string, std::string>> j = {{"CC_Base_BoneRoot", ""},
                                                        {"CC_Base_Hip", "CC_Base_BoneRoot"},
                                                        {"CC_Base_Pelvis", "CC_Base_Hip"},
                                                        {"CC_Base_Waist", "CC_Base_Hip"},
                                                        {"CC_Base_Spine01", "CC_Base_Waist"},
                                                        {"CC_Base_Spine02", "CC_Base_Spine01"},
                                                        {"CC_Base_NeckTwist01", "CC_Base_Spine02"},
                                                        {"CC_Base_NeckTwist02", "CC_Base_NeckTwist01"},
                                                        {"CC_Base_Head", "CC_Base_NeckTwist02"}};
  for (std::string s : {"L", "R"}) {
    const std::string m = "CC_Base_" + s + "_";
    j.insert(j.end(), {{m + "Clavicle", "CC_Base_Spine02"},
                       {m + "Upperarm", m + "Clavicle"},
                       {m + "Forearm", m + "Upperarm"},
                       {m + "Hand", m + "Forearm"},
                       {m + "Thigh", "CC_Base_Pelvis"},
                       {m + "Calf", m + "Thigh"},
                       {m + "Foot", m + "Calf"},
                       {m + "ToeBase", m + "Foot"}});
  }
  if (fingers)
    AddFingers(j, "CC_Base_L_Hand", "CC_Base_R_Hand", {"Thumb", "Index", "Mid", "Ring", "Pinky"},
               [](bool left, const std::string& f, int k) {
                 return std::string("CC_Base_") + (left ? "L_" : "R_") + f + std::to_string(k);
               });
  return Tree(j);
}

TEST(BodyPartMap, MapsMixamoFingersOntoCharacterCreatorsAndBack) {
  const auto mixamo = Mixamo(true), cc = CharacterCreator(true);
  for (bool cc_is_target : {true, false}) {
    const Skeleton& source = cc_is_target ? *mixamo : *cc;
    const Skeleton& target = cc_is_target ? *cc : *mixamo;
    auto map = MapJointsByBodyParts(source, target, {});
    ASSERT_TRUE(map.ok()) << map.status().message();
    const auto pairs = Pairs(source, target, *map);
    for (const std::string side : {"Left", "Right"})
      for (const auto& [mixamo_finger, cc_finger] : std::vector<std::pair<std::string, std::string>>{
               {"Thumb", "Thumb"}, {"Index", "Index"}, {"Middle", "Mid"}, {"Ring", "Ring"}, {"Pinky", "Pinky"}})
        for (int k = 1; k <= 3; ++k) {
          const std::string m = "mixamorig:" + side + "Hand" + mixamo_finger + std::to_string(k);
          const std::string c = "CC_Base_" + side.substr(0, 1) + "_" + cc_finger + std::to_string(k);
          const std::string& t = cc_is_target ? c : m;
          EXPECT_EQ(pairs.count(t) ? pairs.at(t) : "(unmapped)", cc_is_target ? m : c) << t;
        }
  }
  EXPECT_EQ(NormalizeJointName("middle_01_l").base, "middle");
  EXPECT_EQ(NormalizeJointName("LeftHandMiddle2").base, "middle");
  EXPECT_EQ(NormalizeJointName("CC_Base_R_Mid3").base, "middle");
}

TEST(BodyPartMap, MapsMixamoOntoCharacterCreator) {
  const auto source = Mixamo();
  const auto target = CharacterCreator();
  auto map = MapJointsByBodyParts(*source, *target, {});
  ASSERT_TRUE(map.ok()) << map.status().message();
  const auto pairs = Pairs(*source, *target, *map);
  const std::map<std::string, std::string> expected = {
      {"CC_Base_Hip", "mixamorig:Hips"},
      {"CC_Base_Waist", "mixamorig:Spine"},
      {"CC_Base_Spine01", "mixamorig:Spine1"},
      {"CC_Base_Spine02", "mixamorig:Spine2"},
      {"CC_Base_NeckTwist01", "mixamorig:Neck"},
      {"CC_Base_Head", "mixamorig:Head"},
      {"CC_Base_L_Clavicle", "mixamorig:LeftShoulder"},
      {"CC_Base_L_Upperarm", "mixamorig:LeftArm"},
      {"CC_Base_L_Forearm", "mixamorig:LeftForeArm"},
      {"CC_Base_L_Hand", "mixamorig:LeftHand"},
      {"CC_Base_L_Thigh", "mixamorig:LeftUpLeg"},
      {"CC_Base_L_Calf", "mixamorig:LeftLeg"},
      {"CC_Base_L_Foot", "mixamorig:LeftFoot"},
      {"CC_Base_L_ToeBase", "mixamorig:LeftToeBase"},
      {"CC_Base_R_Thigh", "mixamorig:RightUpLeg"},
      {"CC_Base_R_Upperarm", "mixamorig:RightArm"},
  };
  for (const auto& [t, s] : expected) EXPECT_EQ(pairs.count(t) ? pairs.at(t) : "(unmapped)", s) << t;
  EXPECT_EQ(pairs.count("CC_Base_NeckTwist02"), 0u);
  EXPECT_EQ(pairs.count("CC_Base_BoneRoot"), 0u);
  EXPECT_EQ(map->pairs.size() + map->unmapped_target.size(), target->size());
  EXPECT_EQ(map->pairs.size() + map->unmapped_source.size(), source->size());
}

TEST(BodyPartMap, MapsCmuOntoTheDemoCharacterByTopologyWhereNamesDisagree) {
  const auto source = LoadShared("bvh/cmu_01_01.bvh");
  if (!source) GTEST_SKIP() << "../shared/data/bvh/cmu_01_01.bvh is absent";
  const auto target = MakeDemoWalk().clip->skeleton;
  auto map = MapJointsByBodyParts(*source, *target, {});
  ASSERT_TRUE(map.ok()) << map.status().message();
  const auto pairs = Pairs(*source, *target, *map);
  // The demo's "LeftShoulder" is its upper arm (no other joint is), CMU's the clavicle.
  const std::map<std::string, std::string> expected = {
      {"Hips", "Hips"},
      {"Spine", "Spine"},
      {"Chest", "Spine1"},
      {"Neck", "Neck"},
      {"Head", "Head"},
      {"LeftHip", "LeftUpLeg"},
      {"LeftKnee", "LeftLeg"},
      {"LeftAnkle", "LeftFoot"},
      {"LeftToe", "LeftToeBase"},
      {"LeftShoulder", "LeftArm"},
      {"LeftElbow", "LeftForeArm"},
      {"LeftWrist", "LeftHand"},
      {"RightHip", "RightUpLeg"},
      {"RightKnee", "RightLeg"},
      {"RightShoulder", "RightArm"},
      {"RightWrist", "RightHand"},
  };
  for (const auto& [t, s] : expected) EXPECT_EQ(pairs.count(t) ? pairs.at(t) : "(unmapped)", s) << t;
  EXPECT_EQ(map->pairs.size(), target->size());
  std::vector<std::string> unmapped;
  for (int j : map->unmapped_source) unmapped.push_back(source->names[static_cast<size_t>(j)]);
  EXPECT_NE(std::find(unmapped.begin(), unmapped.end(), "LeftShoulder"), unmapped.end());
  EXPECT_NE(std::find(unmapped.begin(), unmapped.end(), "LHipJoint"), unmapped.end());
}

TEST(BodyPartMap, MapsCmuOntoRobotExpressive) {
  const auto source = LoadShared("bvh/cmu_01_01.bvh");
  const auto target = LoadShared("gltf/RobotExpressive/RobotExpressive.glb");
  if (!source || !target) GTEST_SKIP() << "../shared/data (CMU 01_01, RobotExpressive) is absent";
  auto map = MapJointsByBodyParts(*source, *target, {});
  ASSERT_TRUE(map.ok()) << map.status().message();
  const auto pairs = Pairs(*source, *target, *map);
  // Mesh nodes named like bones ("LegL", "ArmL", "HandL", "FootL_1") lose to the bones.
  const std::map<std::string, std::string> expected = {
      {"Hips", "Hips"},
      {"Abdomen", "Spine"},
      {"Torso_1", "Spine1"},
      {"Neck", "Neck"},
      {"Head", "Head"},
      {"UpperLegL", "LeftUpLeg"},
      {"LowerLegL", "LeftLeg"},
      {"FootL", "LeftFoot"},
      {"ShoulderL", "LeftShoulder"},
      {"UpperArmL", "LeftArm"},
      {"LowerArmL", "LeftForeArm"},
      {"UpperLegR", "RightUpLeg"},
      {"LowerLegR", "RightLeg"},
      {"FootR", "RightFoot"},
      {"UpperArmR", "RightArm"},
      {"LowerArmR", "RightForeArm"},
      {"ThumbL", "LThumb"},
  };
  for (const auto& [t, s] : expected) EXPECT_EQ(pairs.count(t) ? pairs.at(t) : "(unmapped)", s) << t;
  for (const char* mesh_node : {"LegL", "ArmL", "HandL", "FootL_1", "LowerLegL_end"})
    EXPECT_EQ(pairs.count(mesh_node), 0u) << mesh_node;
  const std::string hand = pairs.count("Palm1L") ? "Palm1L" : pairs.count("Palm2L") ? "Palm2L" : "Palm3L";
  EXPECT_EQ(pairs.count(hand) ? pairs.at(hand) : "", "LeftHand");
}

TEST(BodyPartMap, ExplicitPairsOverrideAndBadOnesAreNamed) {
  const auto source = Mixamo();
  const auto target = CharacterCreator();
  const std::vector<JointNamePair> explicit_pairs = {{"mixamorig:Spine1", "CC_Base_NeckTwist02"}};
  auto map = MapJointsByBodyParts(*source, *target, explicit_pairs);
  ASSERT_TRUE(map.ok()) << map.status().message();
  const auto pairs = Pairs(*source, *target, *map);
  EXPECT_EQ(pairs.at("CC_Base_NeckTwist02"), "mixamorig:Spine1");
  EXPECT_EQ(pairs.count("CC_Base_Spine01"), 0u);  // its automatic source now drives NeckTwist02

  auto unknown =
      MapJointsByBodyParts(*source, *target, std::vector<JointNamePair>{{"mixamorig:Spine1", "CC_Base_Spine3"}});
  ASSERT_EQ(unknown.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(unknown.status().message().find("map[0].target"), std::string::npos) << unknown.status().message();
  EXPECT_NE(unknown.status().message().find("CC_Base_Spine3"), std::string::npos);

  auto twice = MapJointsByBodyParts(
      *source, *target,
      std::vector<JointNamePair>{{"mixamorig:Spine1", "CC_Base_Head"}, {"mixamorig:Spine2", "CC_Base_Head"}});
  ASSERT_EQ(twice.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(
      twice.status().message().find("map[1]: target joint 'CC_Base_Head' is already mapped from 'mixamorig:Spine1'"),
      std::string::npos)
      << twice.status().message();

  auto source_twice = MapJointsByBodyParts(
      *source, *target,
      std::vector<JointNamePair>{{"mixamorig:Spine1", "CC_Base_Head"}, {"mixamorig:Spine1", "CC_Base_Waist"}});
  ASSERT_EQ(source_twice.status().code(), StatusCode::kInvalidArgument);
  EXPECT_NE(source_twice.status().message().find("map[1]: source joint 'mixamorig:Spine1'"), std::string::npos)
      << source_twice.status().message();
}

}  // namespace
}  // namespace armature
