// Plays a clip as a server stream, paced in real time by the FrameScheduler so no
// thread sleeps while waiting for the next frame.
#pragma once

#include <atomic>
#include <chrono>
#include <mutex>
#include <vector>


#include "armature/v1/poses.grpc.pb.h"
#include "server/asset_store.h"
#include "server/frame_scheduler.h"
#include "server/proto_convert.h"

namespace armature::server {

class StreamClipReactor final : public grpc::ServerWriteReactor<v1::PoseFrame> {
 public:
  // `request` must already be validated; `clip` is held for the stream's life.
  StreamClipReactor(FrameScheduler& scheduler, PartRef<NamedClip> clip, v1::StreamClipRequest request,
                    std::vector<int> joints);

  void OnWriteDone(bool ok) override;
  void OnCancel() override;
  void OnDone() override;

 private:
  // The reactor is deleted when gRPC is done with it (OnDone) and no
  // scheduled frame is pending: either may come last, on any thread.
  void Ref() { refs_.fetch_add(1, std::memory_order_relaxed); }
  void Unref() {
    if (refs_.fetch_sub(1, std::memory_order_acq_rel) == 1) delete this;
  }

  void SendNext();                    // called with mu_ held
  void FinishOnce(grpc::Status status);  // called with mu_ held

  PartRef<NamedClip> clip_;
  v1::StreamClipRequest request_;
  std::vector<int> joints_;
  PoseWorkspace ws_;
  v1::PoseFrame frame_;
  FrameScheduler& scheduler_;
  std::chrono::steady_clock::time_point start_;
  uint64_t index_ = 0;

  std::atomic<int> refs_{1};  // OnDone's
  std::mutex mu_;
  bool cancelled_ = false;
  bool finished_ = false;
  bool write_pending_ = false;
};

}  // namespace armature::server
