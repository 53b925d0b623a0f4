#include "unary_load.h"

#include <condition_variable>
#include <mutex>
#include <random>

#include "armature/v1/meshes.grpc.pb.h"
#include "armature/v1/poses.grpc.pb.h"
#include "grpc/health/v1/health.grpc.pb.h"

namespace armature_load {
namespace {

using Clock = std::chrono::steady_clock;
namespace v1 = armature::v1;
namespace health = grpc::health::v1;

constexpr auto kCallDeadline = std::chrono::seconds(30);

// Counts finished slots; the phase ends when every slot has stopped.
class Latch {
 public:
  explicit Latch(int n) : n_(n) {}
  void CountDown() {
    std::lock_guard lock(mu_);
    if (--n_ == 0) cv_.notify_all();
  }
  void Wait() {
    std::unique_lock lock(mu_);
    cv_.wait(lock, [&] { return n_ == 0; });
  }

 private:
  std::mutex mu_;
  std::condition_variable cv_;
  int n_;
};

class Slot;

// A StreamClip call read to its end; the slot's callback runs in OnDone.
class StreamCall final : public grpc::ClientReadReactor<v1::PoseFrame> {
 public:
  explicit StreamCall(Slot& slot) : slot_(slot) {}
  void Begin(v1::PoseService::Stub& stub, grpc::ClientContext* context, const v1::StreamClipRequest& request) {
    stub.async()->StreamClip(context, &request, this);
    StartRead(&frame_);
    StartCall();
  }
  void OnReadDone(bool ok) override {
    if (ok) StartRead(&frame_);
  }
  void OnDone(const grpc::Status& status) override;

 private:
  Slot& slot_;
  v1::PoseFrame frame_;
};

// One of the `concurrency` closed loops: issues a call, records it when it
// completes, issues the next until the deadline. Its callbacks never overlap.
class Slot {
 public:
  Slot(const std::shared_ptr<grpc::Channel>& channel, const std::vector<MixEntry>& mix, const CallShape& shape,
       int seed, Clock::time_point deadline, Latch& latch)
      : health_(health::Health::NewStub(channel)),
        poses_(v1::PoseService::NewStub(channel)),
        meshes_(v1::MeshService::NewStub(channel)),
        mix_(mix),
        rng_(seed),
        deadline_(deadline),
        latch_(latch) {
    for (const MixEntry& e : mix) total_weight_ += e.weight;
    evaluate_.set_clip(shape.clip);
    evaluate_.set_space(v1::WORLD);
    evaluate_.add_times(0.5);
    skin_.set_mesh(shape.mesh);
    skin_.set_clip(shape.mesh_clip);
    skin_.set_time(0.5);
    stream_.set_clip(shape.clip);
    stream_.set_fps(240);
    stream_.set_duration(shape.stream_frames / 240.0);
    stream_.set_space(v1::WORLD);
  }

  void Next() {
    if (Clock::now() >= deadline_) return latch_.CountDown();
    int pick = static_cast<int>(rng_() % static_cast<unsigned>(total_weight_));
    current_ = mix_.back().rpc;
    for (const MixEntry& e : mix_) {
      if (pick < e.weight) {
        current_ = e.rpc;
        break;
      }
      pick -= e.weight;
    }
    context_ = std::make_unique<grpc::ClientContext>();
    context_->set_deadline(std::chrono::system_clock::now() + kCallDeadline);
    start_ = Clock::now();
    auto done = [this](grpc::Status status) { Done(status); };
    switch (current_) {
      case Rpc::kHealth: health_->async()->Check(context_.get(), &health_request_, &health_response_, done); break;
      case Rpc::kEvaluate: poses_->async()->EvaluateClip(context_.get(), &evaluate_, &evaluate_response_, done); break;
      case Rpc::kSkin: meshes_->async()->SkinMesh(context_.get(), &skin_, &skin_response_, done); break;
      case Rpc::kStream:
        // A reactor is not reused: the one whose OnDone is on the stack now is
        // kept until the next stream call replaces it.
        retired_stream_ = std::move(stream_call_);
        stream_call_ = std::make_unique<StreamCall>(*this);
        stream_call_->Begin(*poses_, context_.get(), stream_);
        break;
    }
  }

  void Done(const grpc::Status& status) {
    RpcOutcome& o = outcome[current_];
    o.latencies_ms.push_back(std::chrono::duration<double, std::milli>(Clock::now() - start_).count());
    if (!status.ok() && o.errors++ == 0) o.first_error = status.error_message();
    Next();
  }

  std::map<Rpc, RpcOutcome> outcome;

 private:
  std::unique_ptr<health::Health::Stub> health_;
  std::unique_ptr<v1::PoseService::Stub> poses_;
  std::unique_ptr<v1::MeshService::Stub> meshes_;
  const std::vector<MixEntry>& mix_;
  int total_weight_ = 0;
  std::mt19937 rng_;
  const Clock::time_point deadline_;
  Latch& latch_;

  Rpc current_ = Rpc::kHealth;
  std::unique_ptr<grpc::ClientContext> context_;
  Clock::time_point start_;
  health::HealthCheckRequest health_request_;
  health::HealthCheckResponse health_response_;
  v1::EvaluateClipRequest evaluate_;
  v1::EvaluateClipResponse evaluate_response_;
  v1::SkinMeshRequest skin_;
  v1::SkinMeshResponse skin_response_;
  v1::StreamClipRequest stream_;
  std::unique_ptr<StreamCall> stream_call_, retired_stream_;
};

void StreamCall::OnDone(const grpc::Status& status) { slot_.Done(status); }

}  // namespace

bool RpcFromName(const std::string& name, Rpc& rpc) {
  if (name == "health") return rpc = Rpc::kHealth, true;
  if (name == "evaluate") return rpc = Rpc::kEvaluate, true;
  if (name == "skin") return rpc = Rpc::kSkin, true;
  if (name == "stream") return rpc = Rpc::kStream, true;
  return false;
}

const char* RpcLabel(Rpc rpc) {
  switch (rpc) {
    case Rpc::kHealth: return "Health/Check";
    case Rpc::kEvaluate: return "PoseService/EvaluateClip";
    case Rpc::kSkin: return "MeshService/SkinMesh";
    case Rpc::kStream: return "PoseService/StreamClip";
  }
  return "?";
}

PhaseOutcome RunClosedLoop(const std::vector<std::shared_ptr<grpc::Channel>>& channels,
                           const std::vector<MixEntry>& mix, const CallShape& shape, int concurrency, double seconds) {
  Latch latch(concurrency);
  const auto start = Clock::now();
  const auto deadline = start + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(seconds));
  std::vector<std::unique_ptr<Slot>> slots;
  for (int i = 0; i < concurrency; ++i)
    slots.push_back(std::make_unique<Slot>(channels[i % channels.size()], mix, shape, 7919 * (i + 1), deadline, latch));
  for (auto& slot : slots) slot->Next();
  latch.Wait();
  PhaseOutcome phase;
  phase.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  for (auto& slot : slots)
    for (auto& [rpc, o] : slot->outcome) {
      RpcOutcome& into = phase.by_rpc[rpc];
      into.latencies_ms.insert(into.latencies_ms.end(), o.latencies_ms.begin(), o.latencies_ms.end());
      if (o.errors > 0 && into.errors == 0) into.first_error = o.first_error;
      into.errors += o.errors;
    }
  return phase;
}

}  // namespace armature_load
