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

ClientOptions OptionsFor(const ServerProcess& server) {
  ClientOptions o;
  o.target = server.target();
  o.timeout = std::chrono::seconds(30);
  return o;
}

std::filesystem::path WriteTemp(const TempDir& dir, const std::string& name, const std::string& content) {
  const std::filesystem::path p = dir.path() / name;
  std::ofstream(p, std::ios::binary) << content;
  return p;
}

grpc::StatusCode CodeOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const ClientError& e) {
    return e.code();
  }
  return grpc::StatusCode::OK;
}

std::string MessageOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const ClientError& e) {
    return e.what();
  }
  return "";
}

bool WaitFor(const std::function<bool()>& condition, double seconds) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!condition()) {
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return true;
}

}  // namespace armature::testing
