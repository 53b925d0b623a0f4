// The closed-loop driver of armature-load: `concurrency` calls always in
// flight (each slot issues its next call from the previous one's callback,
// gRPC's callback API), picking the RPC by weight from the mix, for a fixed
// wall-clock time. Latency is measured per call from issue to completion.
#pragma once

#include <chrono>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <grpcpp/grpcpp.h>

namespace armature_load {

enum class Rpc { kHealth, kEvaluate, kSkin, kStream };

// "health", "evaluate", "skin", "stream"; false for any other name.
bool RpcFromName(const std::string& name, Rpc& rpc);
const char* RpcLabel(Rpc rpc);  // the gRPC method, e.g. "PoseService/EvaluateClip"

struct MixEntry {
  Rpc rpc;
  int weight;
};

// What each RPC of the mix asks for.
struct CallShape {
  std::string clip = "load_cmu";             // EvaluateClip (one pose) and StreamClip
  std::string mesh = "demo_character.body";  // SkinMesh
  std::string mesh_clip = "demo_character.walk";
  int stream_frames = 12;  // a StreamClip call: this many frames at 240 fps
};

struct RpcOutcome {
  std::vector<double> latencies_ms;
  int64_t errors = 0;
  std::string first_error;
};

struct PhaseOutcome {
  double seconds = 0;  // wall time from the first call to the last completion
  std::map<Rpc, RpcOutcome> by_rpc;
};

// Runs the mix over `channels` (slot i uses channel i % size) for `seconds`;
// every slot finishes its call in flight before this returns.
PhaseOutcome RunClosedLoop(const std::vector<std::shared_ptr<grpc::Channel>>& channels,
                           const std::vector<MixEntry>& mix, const CallShape& shape, int concurrency, double seconds);

}  // namespace armature_load
