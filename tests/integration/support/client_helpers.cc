#include "client_helpers.h"

#include <chrono>
#include <fstream>
#include <thread>

namespace armature::testing {

std::string ArmBvhWithFrames(int frames) {
  std::string bvh(kArmBvh, std::string_view(kArmBvh).find("MOTION"));
  bvh += "MOTION\nFrames: " + std::to_string(frames) + "\nFrame Time: 0.5\n";
  for (int f = 0; f < frames; ++f) bvh += "0 0 0 " + std::to_string(f % 360) + " 0 0 0 0 0\n";
  return bvh;
}

client::ClientOptions OptionsFor(const ServerProcess& server) {
  client::ClientOptions o;
  o.target = server.target();
  o.timeout = std::chrono::seconds(30);
  return o;
}

std::filesystem::path WriteTemp(const TempDir& dir, const std::string& name, const std::string& content) {
  const std::filesystem::path p = dir.path() / name;
  std::ofstream(p, std::ios::binary) << content;
  return p;
}

grpc::Status StatusOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const client::ClientError& e) {
    return grpc::Status(e.code(), e.what());
  }
  return grpc::Status::OK;
}

grpc::StatusCode CodeOf(const std::function<void()>& call) { return StatusOf(call).error_code(); }

std::string MessageOf(const std::function<void()>& call) { return StatusOf(call).error_message(); }

bool WaitFor(const std::function<bool()>& condition, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!condition()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

std::set<std::string> AssetNames(client::Client& client) {
  std::set<std::string> names;
  const auto listed = client.ListAssets();
  for (const auto& a : listed.assets()) names.insert(a.name());
  return names;
}

}  // namespace armature::testing
