// What the integration tests share on the client side: a small BVH the
// tests write themselves, client options for a ServerProcess, and status
// helpers.
#pragma once

#include <filesystem>
#include <functional>
#include <string>

#include "armature/client.h"
#include "server_process.h"

namespace armature::testing {

// A two-joint arm written by the test: the root at (1,2,3) + position
// channels, rotating about Z by 90°·frame; the child 2 units along X.
inline constexpr char kArmBvh[] = R"(HIERARCHY
ROOT Base
{
  OFFSET 1 2 3
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT Tip
  {
    OFFSET 2 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 1 0 0
    }
  }
}
MOTION
Frames: 3
Frame Time: 0.5
0 0 0 0 0 0 0 0 0
0 0 0 90 0 0 0 0 0
0 0 0 180 0 0 0 0 0
)";

// The same arm with `frames` frames, turning 1° about Z per frame.
std::string ArmBvhWithFrames(int frames);

ClientOptions OptionsFor(const ServerProcess& server);
std::filesystem::path WriteTemp(const TempDir& dir, const std::string& name, const std::string& content);

// The status code a call throws (OK if none), and its message ("" if none).
grpc::StatusCode CodeOf(const std::function<void()>& call);
std::string MessageOf(const std::function<void()>& call);

// Polls `condition` every 20 ms until it holds or `seconds` pass; returns whether it held.
bool WaitFor(const std::function<bool()>& condition, double seconds);

}  // namespace armature::testing
