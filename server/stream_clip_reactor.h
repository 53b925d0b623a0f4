// Plays a clip as a server stream, paced in real time by a gRPC alarm so no
// thread sleeps while waiting for the next frame.
#pragma once

#include <chrono>
#include <mutex>
#include <vector>

#include <grpcpp/alarm.h>

#include "armature/v1/poses.grpc.pb.h"
#include "server/asset_store.h"
#include "server/proto_convert.h"

namespace armature::server {

class StreamClipReactor final : public grpc::ServerWriteReactor<v1::PoseFrame> {
 public:
  // `request` must already be validated; `clip` is held for the stream's life.
  StreamClipReactor(PartRef<NamedClip> clip, v1::StreamClipRequest request, std::vector<int> joints);

  void OnWriteDone(bool ok) override;
  void OnCancel() override;
  void OnDone() override { delete this; }

 private:
  void SendNext();                    // called with mu_ held
  void FinishOnce(grpc::Status status);  // called with mu_ held

  PartRef<NamedClip> clip_;
  v1::StreamClipRequest request_;
  std::vector<int> joints_;
  PoseWorkspace ws_;
  v1::PoseFrame frame_;
  grpc::Alarm alarm_;
  std::chrono::steady_clock::time_point start_;
  uint64_t index_ = 0;

  std::mutex mu_;
  bool cancelled_ = false;
  bool finished_ = false;
};

}  // namespace armature::server
