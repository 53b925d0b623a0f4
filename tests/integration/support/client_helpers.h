// What the integration tests share on the client side: a small BVH the
// tests write themselves, client options for a ServerProcess, and status
// helpers.
#pragma once

#include <filesystem>
#include <functional>
#include <set>
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

client::ClientOptions OptionsFor(const ServerProcess& server);
std::filesystem::path WriteTemp(const TempDir& dir, const std::string& name, const std::string& content);

// The status a call throws (OK if none), its code and its message ("" if none).
grpc::Status StatusOf(const std::function<void()>& call);
grpc::StatusCode CodeOf(const std::function<void()>& call);
std::string MessageOf(const std::function<void()>& call);

// Polls `condition` every 20 ms until it holds or `seconds` pass; returns whether it held.
bool WaitFor(const std::function<bool()>& condition, double seconds);

// How long replicas sharing a data dir are given to see each other's changes.
// They poll the manifest every 500 ms; the bound is generous so that a loaded
// machine cannot fail a test that asserts that changes propagate, not how fast.
inline constexpr double kPropagationTimeoutSeconds = 30.0;

// The names of the assets `client`'s server lists.
std::set<std::string> AssetNames(client::Client& client);

}  // namespace armature::testing
