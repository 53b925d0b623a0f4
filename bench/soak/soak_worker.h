// One soak client: weighted random calls of the mix until a deadline, each
// timed and tallied. The calls cover every surface: unary, streams and
// sessions over gRPC, authoring (bake, retarget), and the HTTP port's
// gRPC-Web, binary REST and WebSocket sessions.
#pragma once

#include <chrono>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "armature/client.h"
#include "soak_http.h"
#include "soak_stats.h"

namespace armature::soak {

struct Mix {
  std::vector<std::pair<std::string, int>> weights;
  int total = 0;
};

// The entries a --mix may name.
const std::vector<std::string>& MixEntries();

// The soak's own deformed mesh: an 8×8 vertex sheet as OBJ (the asset soak_grid).
std::string GridObj();

class Worker {
 public:
  Worker(const std::string& target, int http_port, int id, const Mix& mix, Stats& stats);
  void Run(std::chrono::steady_clock::time_point deadline);

 private:
  void Call(const std::string& kind);
  void Timed(const std::string& method, const std::function<void()>& call);
  void TimedStatus(const std::string& method, const std::function<grpc::Status()>& call);
  double Jitter(double scale) { return scale * (static_cast<double>(rng_() % 1000) / 1000.0 - 0.5); }
  double ClipTime() { return static_cast<double>(rng_() % 3000) / 1000.0; }
  v1::SolveIkRequest IkStart();
  v1::EvaluateClipRequest Evaluate();
  v1::Motion ThreeLayers();
  std::string Name(const std::string& kind) {
    return "soak_" + kind + std::to_string(id_) + "_" + std::to_string(next_++);
  }

  void CallEvaluate();
  void CallStream();
  void CallIkSession();
  void CallDeform();
  void CallList();
  void CallImportDelete();
  void CallBake();
  void CallRetarget();
  void CallPlayback();
  void CallWebSocketSession();
  // An authoring call that stores the asset `asset`, timed, then its deletion.
  void MakeThenDelete(const std::string& method, const std::string& asset,
                      const std::function<grpc::Status(grpc::ClientContext&)>& make);

  int id_;
  const Mix& mix_;
  Stats& stats_;
  std::mt19937 rng_;
  std::unique_ptr<client::Client> client_;
  HttpTransports http_;
  bool has_http_;
  int next_ = 0;
};

}  // namespace armature::soak
