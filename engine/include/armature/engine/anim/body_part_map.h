// Which joint of one skeleton plays which joint of another, when their names
// differ (CMU "LeftUpLeg", RobotExpressive "UpperLegL", mixamo
// "mixamorig:LeftUpLeg", Character Creator "CC_Base_L_Thigh", the demo
// character's "LeftHip"): retargeting's joint map. Names are normalized and
// read as body parts through a table of synonyms; the topology settles what
// names leave open (a limb's parts are chained from the body outwards, "Shoulder"
// is the upper arm when no other joint of that side is, the spine's joints are
// matched along the chain from the hips to the neck). No I/O, no proto.
#pragma once

#include <array>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "armature/base/status.h"
#include "armature/engine/anim/skeleton.h"

namespace armature {

enum class BodySide : unsigned char { kCenter, kLeft, kRight };

// A joint name read as parts: "mixamorig:LeftForeArm" → side kLeft, base
// "forearm"; "UpperLegL" → kLeft, "upperleg"; "Spine1" → kCenter, "spine",
// number 1; "Head_end" → "head", tip.
struct JointNameKey {
  BodySide side = BodySide::kCenter;
  std::string base;  // lower case, no separators, no side, no number
  int number = -1;   // a trailing number ("Spine1", "Torso_1"), or -1
  bool tip = false;  // "_end", "End", "Nub", "Tip": a bone's end, not a joint to drive
};

JointNameKey NormalizeJointName(std::string_view name);

// The body parts a skeleton's joints were read as (joint indices, -1 when
// absent).
struct LimbJoints {
  int root = -1;   // clavicle (arm) or -1 (legs)
  int upper = -1;  // upper arm / thigh
  int lower = -1;  // forearm / shin
  int end = -1;    // hand / foot
  int tip = -1;    // toe (legs)
};

struct BodyParts {
  int hips = -1;
  std::vector<int> spine;  // from the hips up to the neck, both excluded
  int neck = -1;
  int head = -1;
  std::array<LimbJoints, 2> arms;  // [0] left, [1] right
  std::array<LimbJoints, 2> legs;
};

BodyParts FindBodyParts(const Skeleton& skeleton);

struct JointPairIndex {
  int source = -1;
  int target = -1;
};

struct JointNamePair {
  std::string source;
  std::string target;
};

// Retargeting's joint map, read through body parts (anim/joint_map's
// MapJointsByName is the other one: the same names, joint by joint).
struct BodyPartMap {
  std::vector<JointPairIndex> pairs;  // in target joint order
  std::vector<int> unmapped_source;   // ascending
  std::vector<int> unmapped_target;
  BodyParts source_parts;
  BodyParts target_parts;
};

// The automatic map from `source` onto `target`, with `explicit_pairs`
// replacing the automatic pairs of the joints they name. Each target joint
// is driven by at most one source joint and each source joint drives at most
// one target joint. INVALID_ARGUMENT naming the entry ("map[1].target:
// unknown joint 'Foo' …", "map[2]: target joint 'Head' is already mapped
// from 'Head' by map[0]") for unknown or repeated joints.
StatusOr<BodyPartMap> MapJointsByBodyParts(const Skeleton& source, const Skeleton& target,
                                           std::span<const JointNamePair> explicit_pairs);

}  // namespace armature
