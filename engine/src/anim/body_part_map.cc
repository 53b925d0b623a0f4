#include "armature/engine/anim/body_part_map.h"

#include <algorithm>
#include <cctype>
#include <limits>
#include <cmath>
#include <map>
#include <tuple>
#include <optional>

#include "armature/base/closest_name.h"

namespace armature {
namespace {

std::string Lower(std::string_view s) {
  std::string out(s);
  for (char& c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

bool StartsWith(std::string_view s, std::string_view prefix) { return s.substr(0, prefix.size()) == prefix; }

// Exporters' namespaces before the body part's name.
constexpr std::string_view kPrefixes[] = {"mixamorig_", "mixamorig", "cc_base_", "bip001_", "bip001 ", "bip001",
                                          "bip01_",     "bip01 ",    "bip01",    "def-",    "def_",    "b_"};

// One name per finger: Mixamo's "HandThumb1", Character Creator's "Thumb1" and "Mid1", Unreal's
// "middle_01" (and "little", "pinkie") read alike, so the fingers pair by name.
std::string CanonicalFinger(const std::string& base) {
  constexpr std::pair<std::string_view, std::string_view> kFingers[] = {
      {"thumb", "thumb"}, {"index", "index"}, {"middle", "middle"}, {"mid", "middle"},
      {"ring", "ring"},   {"pinky", "pinky"}, {"pinkie", "pinky"},  {"little", "pinky"}};
  std::string_view rest = base;
  if (StartsWith(rest, "hand") && rest.size() > 4) rest.remove_prefix(4);
  for (const auto& [word, canonical] : kFingers)
    if (rest == word) return std::string(canonical);
  return base;
}

// Splits at separators, lower→upper ("upLeg"), upper→Upper+lower ("LHip")
// and letter↔digit boundaries.
std::vector<std::string> Tokens(std::string_view s) {
  std::vector<std::string> tokens;
  std::string current;
  auto flush = [&] {
    if (!current.empty()) tokens.push_back(Lower(current));
    current.clear();
  };
  for (size_t i = 0; i < s.size(); ++i) {
    const unsigned char c = static_cast<unsigned char>(s[i]);
    if (!std::isalnum(c)) {
      flush();
      continue;
    }
    if (!current.empty()) {
      const unsigned char prev = static_cast<unsigned char>(current.back());
      const bool next_lower = i + 1 < s.size() && std::islower(static_cast<unsigned char>(s[i + 1]));
      if ((std::islower(prev) && std::isupper(c)) || (std::isupper(prev) && std::isupper(c) && next_lower) ||
          (std::isdigit(prev) != 0) != (std::isdigit(c) != 0))
        flush();
    }
    current.push_back(static_cast<char>(c));
  }
  flush();
  return tokens;
}

enum class Part : unsigned char {
  kNone,
  kHips,
  kNeck,
  kHead,
  kClavicle,
  kShoulder,
  kUpperArm,
  kForeArm,
  kHand,
  kThigh,
  kSideHip,
  kShin,
  kFoot,
  kToe,
};

struct Synonym {
  std::string_view base;
  Part part;
  int rank;  // the more specific names first, so "UpperArmL" wins over a mesh node "ArmL"
};

constexpr Synonym kSynonyms[] = {
    {"hips", Part::kHips, 0},         {"pelvis", Part::kHips, 0},       {"hip", Part::kHips, 1},
    {"neck", Part::kNeck, 0},         {"necktwist", Part::kNeck, 1},    {"head", Part::kHead, 0},
    {"clavicle", Part::kClavicle, 0}, {"collar", Part::kClavicle, 0},   {"collarbone", Part::kClavicle, 0},
    {"shoulder", Part::kShoulder, 0}, {"upperarm", Part::kUpperArm, 0}, {"uparm", Part::kUpperArm, 0},
    {"arm", Part::kUpperArm, 1},      {"forearm", Part::kForeArm, 0},   {"lowerarm", Part::kForeArm, 0},
    {"elbow", Part::kForeArm, 1},     {"hand", Part::kHand, 0},         {"wrist", Part::kHand, 1},
    {"palm", Part::kHand, 2},         {"upleg", Part::kThigh, 0},       {"upperleg", Part::kThigh, 0},
    {"thigh", Part::kThigh, 0},       {"lowerleg", Part::kShin, 0},     {"calf", Part::kShin, 0},
    {"shin", Part::kShin, 0},         {"knee", Part::kShin, 1},         {"leg", Part::kShin, 2},
    {"foot", Part::kFoot, 0},         {"ankle", Part::kFoot, 1},        {"toebase", Part::kToe, 0},
    {"toe", Part::kToe, 0},           {"toes", Part::kToe, 0},          {"ball", Part::kToe, 1},
};

struct Candidate {
  int joint;
  Part part;
  BodySide side;
  int order;  // smaller is better: synonym rank, then unnumbered, then number
};

class Topology {
 public:
  explicit Topology(const Skeleton& s) : s_(s) {}
  bool IsAncestor(int ancestor, int joint) const {
    for (int j = joint; j >= 0; j = s_.parents[static_cast<size_t>(j)])
      if (j == ancestor) return true;
    return false;
  }
  // ancestor … joint, both excluded, or nullopt when not an ancestor.
  std::optional<std::vector<int>> Between(int ancestor, int joint) const {
    if (ancestor < 0 || joint < 0 || !IsAncestor(ancestor, joint) || ancestor == joint) return std::nullopt;
    std::vector<int> path;
    for (int j = s_.parents[static_cast<size_t>(joint)]; j != ancestor; j = s_.parents[static_cast<size_t>(j)])
      path.push_back(j);
    std::reverse(path.begin(), path.end());
    return path;
  }

 private:
  const Skeleton& s_;
};

std::vector<Candidate> ReadCandidates(const Skeleton& skeleton) {
  std::vector<Candidate> out;
  for (size_t j = 0; j < skeleton.size(); ++j) {
    const JointNameKey key = NormalizeJointName(skeleton.names[j]);
    if (key.tip) continue;
    for (const Synonym& syn : kSynonyms) {
      if (syn.base != key.base) continue;
      Part part = syn.part;
      if (part == Part::kHips && key.side != BodySide::kCenter) part = Part::kSideHip;
      out.push_back({static_cast<int>(j), part, key.side,
                     syn.rank * 1000 + (key.number < 0 ? 0 : 1 + std::min(key.number, 998))});
      break;
    }
  }
  std::stable_sort(out.begin(), out.end(), [](const Candidate& a, const Candidate& b) { return a.order < b.order; });
  return out;
}

class PartPicker {
 public:
  PartPicker(const Skeleton& s, std::vector<Candidate> candidates) : topology_(s), candidates_(std::move(candidates)) {}

  bool Has(Part part, BodySide side) const {
    return std::any_of(candidates_.begin(), candidates_.end(),
                       [&](const Candidate& c) { return c.part == part && c.side == side; });
  }
  // The best candidate below `below` (when ≥ 0), else (when `fallback`) the best of any.
  int Pick(Part part, BodySide side, int below = -1, bool fallback = true) const {
    int any = -1;
    for (const Candidate& c : candidates_) {
      if (c.part != part || c.side != side) continue;
      if (below < 0 || topology_.IsAncestor(below, c.joint)) return c.joint;
      if (any < 0) any = c.joint;
    }
    return fallback ? any : -1;
  }
  int PickAbove(Part part, BodySide side, int above) const {
    for (const Candidate& c : candidates_)
      if (c.part == part && c.side == side && (above < 0 || topology_.IsAncestor(c.joint, above))) return c.joint;
    return -1;
  }
  const Topology& topology() const { return topology_; }

 private:
  Topology topology_;
  std::vector<Candidate> candidates_;
};

LimbJoints FindArm(const PartPicker& p, BodySide side) {
  LimbJoints arm;
  // "Shoulder" is the clavicle beside an upper arm (CMU, mixamo), else the upper arm (the demo character).
  const bool shoulder_is_clavicle = p.Has(Part::kUpperArm, side);
  arm.upper = p.Pick(shoulder_is_clavicle ? Part::kUpperArm : Part::kShoulder, side);
  arm.lower = p.Pick(Part::kForeArm, side, arm.upper, arm.upper < 0);
  arm.end = p.Pick(Part::kHand, side, arm.lower >= 0 ? arm.lower : arm.upper);
  arm.root = p.PickAbove(Part::kClavicle, side, arm.upper);
  if (arm.root < 0 && shoulder_is_clavicle) arm.root = p.PickAbove(Part::kShoulder, side, arm.upper);
  if (arm.root == arm.upper) arm.root = -1;
  return arm;
}

LimbJoints FindLeg(const PartPicker& p, BodySide side) {
  LimbJoints leg;
  // A side's "Hip" is the thigh when nothing else is (the demo character's LeftHip), else
  // a joint before it (CMU's LHipJoint is "hipjoint", not read at all).
  leg.upper = p.Pick(p.Has(Part::kThigh, side) ? Part::kThigh : Part::kSideHip, side);
  leg.lower = p.Pick(Part::kShin, side, leg.upper, leg.upper < 0);
  leg.end = p.Pick(Part::kFoot, side, leg.lower >= 0 ? leg.lower : leg.upper);
  leg.tip = p.Pick(Part::kToe, side, leg.end, leg.end < 0);
  return leg;
}

// Target chain joint i of m takes source joint round((i+1)·n/m) − 1 of n: the
// top ends meet (chest to chest) and the rest spread evenly.
void PairChains(const std::vector<int>& source, const std::vector<int>& target, std::vector<JointPairIndex>& pairs) {
  const size_t n = source.size(), m = target.size();
  if (n == 0 || m == 0) return;
  int last = -1;
  for (size_t i = 0; i < m; ++i) {
    const int k =
        static_cast<int>(std::lround(static_cast<double>(i + 1) * static_cast<double>(n) / static_cast<double>(m))) - 1;
    if (k <= last || k < 0) continue;
    pairs.push_back({source[static_cast<size_t>(k)], target[i]});
    last = k;
  }
}

void PairLimb(const LimbJoints& s, const LimbJoints& t, std::vector<JointPairIndex>& pairs) {
  const int sj[] = {s.root, s.upper, s.lower, s.end, s.tip};
  const int tj[] = {t.root, t.upper, t.lower, t.end, t.tip};
  for (int k = 0; k < 5; ++k)
    if (sj[k] >= 0 && tj[k] >= 0) pairs.push_back({sj[k], tj[k]});
}

Status UnknownJointIn(size_t entry, std::string_view field, std::string_view name, const Skeleton& skeleton) {
  return Status::InvalidArgument("map[" + std::to_string(entry) + "]." + std::string(field) + ": " +
                                 UnknownJoint(name, skeleton.names));
}

}  // namespace

JointNameKey NormalizeJointName(std::string_view name) {
  JointNameKey key;
  const size_t colon = name.find_last_of(":|");
  if (colon != std::string_view::npos) name = name.substr(colon + 1);
  const std::string lower = Lower(name);
  for (std::string_view prefix : kPrefixes) {
    if (StartsWith(lower, prefix) && lower.size() > prefix.size()) {
      name = name.substr(prefix.size());
      break;
    }
  }
  for (std::string& token : Tokens(name)) {
    if (token == "left" || token == "l") {
      key.side = BodySide::kLeft;
    } else if (token == "right" || token == "r") {
      key.side = BodySide::kRight;
    } else if (token == "end" || token == "nub" || token == "tip" || token == "site") {
      key.tip = true;
    } else if (std::isdigit(static_cast<unsigned char>(token[0]))) {
      key.number = token.size() > 6 ? 999999 : std::stoi(token);
    } else {
      // An all-lower-case "leftupleg" has no boundary to split at.
      if (StartsWith(token, "left") && token.size() > 4) {
        key.side = BodySide::kLeft;
        token = token.substr(4);
      } else if (StartsWith(token, "right") && token.size() > 5) {
        key.side = BodySide::kRight;
        token = token.substr(5);
      }
      key.base += token;
    }
  }
  key.base = CanonicalFinger(key.base);
  return key;
}

BodyParts FindBodyParts(const Skeleton& skeleton) {
  PartPicker picker(skeleton, ReadCandidates(skeleton));
  BodyParts parts;
  for (int s = 0; s < 2; ++s) {
    const BodySide side = s == 0 ? BodySide::kLeft : BodySide::kRight;
    parts.arms[static_cast<size_t>(s)] = FindArm(picker, side);
    parts.legs[static_cast<size_t>(s)] = FindLeg(picker, side);
  }
  // The hips the spine rises from (Character Creator's Pelvis carries only the legs, its Hip the waist).
  parts.hips = picker.PickAbove(Part::kHips, BodySide::kCenter, picker.Pick(Part::kNeck, BodySide::kCenter));
  if (parts.hips < 0) parts.hips = picker.Pick(Part::kHips, BodySide::kCenter);
  parts.neck = picker.Pick(Part::kNeck, BodySide::kCenter, parts.hips);
  parts.head = picker.Pick(Part::kHead, BodySide::kCenter, parts.neck >= 0 ? parts.neck : parts.hips);
  const int spine_top = parts.neck >= 0 ? parts.neck : parts.head;
  if (auto spine = picker.topology().Between(parts.hips, spine_top)) parts.spine = std::move(*spine);
  return parts;
}

StatusOr<BodyPartMap> MapJointsByBodyParts(const Skeleton& source, const Skeleton& target,
                                           std::span<const JointNamePair> explicit_pairs) {
  BodyPartMap map;
  map.source_parts = FindBodyParts(source);
  map.target_parts = FindBodyParts(target);
  const BodyParts& s = map.source_parts;
  const BodyParts& t = map.target_parts;

  std::vector<JointPairIndex> automatic;
  if (s.hips >= 0 && t.hips >= 0) automatic.push_back({s.hips, t.hips});
  PairChains(s.spine, t.spine, automatic);
  if (s.neck >= 0 && t.neck >= 0) automatic.push_back({s.neck, t.neck});
  if (s.head >= 0 && t.head >= 0) automatic.push_back({s.head, t.head});
  for (size_t side = 0; side < 2; ++side) {
    PairLimb(s.arms[side], t.arms[side], automatic);
    PairLimb(s.legs[side], t.legs[side], automatic);
  }

  std::vector<int> source_of(target.size(), -1), target_of(source.size(), -1);
  auto add = [&](int sj, int tj) {
    if (sj < 0 || tj < 0 || source_of[static_cast<size_t>(tj)] >= 0 || target_of[static_cast<size_t>(sj)] >= 0) return;
    source_of[static_cast<size_t>(tj)] = sj;
    target_of[static_cast<size_t>(sj)] = tj;
  };

  // Explicit pairs first: they win over anything automatic on either joint.
  std::vector<int> explicit_entry_of_target(target.size(), -1), explicit_entry_of_source(source.size(), -1);
  for (size_t e = 0; e < explicit_pairs.size(); ++e) {
    const JointNamePair& pair = explicit_pairs[e];
    const int sj = source.Find(pair.source);
    if (sj < 0) return UnknownJointIn(e, "source", pair.source, source);
    const int tj = target.Find(pair.target);
    if (tj < 0) return UnknownJointIn(e, "target", pair.target, target);
    if (const int prev = explicit_entry_of_target[static_cast<size_t>(tj)]; prev >= 0)
      return Status::InvalidArgument("map[" + std::to_string(e) + "]: target joint '" + pair.target +
                                     "' is already mapped from '" + explicit_pairs[static_cast<size_t>(prev)].source +
                                     "' by map[" + std::to_string(prev) + "]; a target joint takes one source joint");
    if (const int prev = explicit_entry_of_source[static_cast<size_t>(sj)]; prev >= 0)
      return Status::InvalidArgument("map[" + std::to_string(e) + "]: source joint '" + pair.source +
                                     "' already drives '" + explicit_pairs[static_cast<size_t>(prev)].target +
                                     "' by map[" + std::to_string(prev) + "]; a source joint drives one target joint");
    explicit_entry_of_target[static_cast<size_t>(tj)] = static_cast<int>(e);
    explicit_entry_of_source[static_cast<size_t>(sj)] = static_cast<int>(e);
    add(sj, tj);
  }
  for (const JointPairIndex& p : automatic) add(p.source, p.target);

  // Joints no body part claims but named alike on both sides (fingers: CMU "LThumb", RobotExpressive "ThumbL").
  std::map<std::tuple<int, std::string, int>, int> source_by_key;
  for (size_t j = 0; j < source.size(); ++j) {
    if (target_of[j] >= 0) continue;
    const JointNameKey key = NormalizeJointName(source.names[j]);
    if (!key.tip && !key.base.empty())
      source_by_key.emplace(std::make_tuple(static_cast<int>(key.side), key.base, key.number), static_cast<int>(j));
  }
  for (size_t j = 0; j < target.size(); ++j) {
    if (source_of[j] >= 0) continue;
    const JointNameKey key = NormalizeJointName(target.names[j]);
    if (key.tip) continue;
    auto it = source_by_key.find(std::make_tuple(static_cast<int>(key.side), key.base, key.number));
    if (it != source_by_key.end()) add(it->second, static_cast<int>(j));
  }

  for (size_t j = 0; j < target.size(); ++j) {
    if (source_of[j] >= 0)
      map.pairs.push_back({source_of[j], static_cast<int>(j)});
    else
      map.unmapped_target.push_back(static_cast<int>(j));
  }
  for (size_t j = 0; j < source.size(); ++j)
    if (target_of[j] < 0) map.unmapped_source.push_back(static_cast<int>(j));
  return map;
}

}  // namespace armature
