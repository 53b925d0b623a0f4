// The crowd tests' commands: a start and an add, the same over gRPC and over
// the WebSocket route.
#pragma once

#include <algorithm>
#include <cstdint>
#include <cmath>
#include <string>
#include <vector>

#include "armature/client.h"
#include "armature/v1/crowd.pb.h"

namespace armature::testing {

// The angle between two quaternions (w, x, y, z each), sign-blind. From the
// chord, 4·asin(|a ∓ b| / 2), not acos of the dot, which float32 rounding
// swamps near 0 (≈ 1e-3 rad).
inline double Angle(const float* a, const float* b) {
  double na = 0, nb = 0, minus = 0, plus = 0;
  for (int k = 0; k < 4; ++k) na += double(a[k]) * a[k], nb += double(b[k]) * b[k];
  for (int k = 0; k < 4; ++k) {
    const double x = a[k] / std::sqrt(na), y = b[k] / std::sqrt(nb);
    minus += (x - y) * (x - y), plus += (x + y) * (x + y);
  }
  return 4 * std::asin(std::min(1.0, std::sqrt(std::min(minus, plus)) / 2));
}

inline v1::CrowdCommand AddCommand(uint32_t id, const std::string& clip, double offset, double speed = 1) {
  v1::CrowdCommand c;
  c.mutable_add()->set_id(id);
  c.mutable_add()->set_clip(clip);
  c.mutable_add()->set_time_offset(offset);
  c.mutable_add()->set_speed(speed);
  c.mutable_add()->set_significance(-static_cast<double>(id));
  return c;
}

inline v1::CrowdCommand StartCommand(double duration) {  // 30 ticks a second for `duration`
  v1::CrowdCommand start;
  start.mutable_start()->set_fps(30);
  start.mutable_start()->set_duration(duration);
  return start;
}

// RobotExpressive's skeleton (the suite imports it as asset "robot"); empty when absent.
inline std::string RobotSkeleton(client::Client& client) {
  const v1::ListSkeletonsResponse skeletons = client.ListSkeletons();
  for (const v1::SkeletonInfo& s : skeletons.skeletons())
    if (s.asset() == "robot") return s.name();
  return "";
}

// A 0.4 s session whose commands after the first add are refused, in order:
// id 1 again (ALREADY_EXISTS), CMU's clip on the robot (INVALID_ARGUMENT), a
// NaN significance (INVALID_ARGUMENT), removing id 44 (NOT_FOUND).
inline std::vector<v1::CrowdCommand> RefusedCommands(const std::string& robot_skeleton) {
  std::vector<v1::CrowdCommand> commands = {StartCommand(0.4), AddCommand(1, "cmu", 0), AddCommand(1, "cmu", 0)};
  commands.push_back(AddCommand(2, "cmu", 0));
  commands.back().mutable_add()->set_skeleton(robot_skeleton);
  commands.push_back(AddCommand(3, "cmu", 0));
  commands.back().mutable_add()->set_significance(std::nan(""));
  commands.emplace_back().set_remove(44);
  return commands;
}

}  // namespace armature::testing
