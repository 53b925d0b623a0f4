// One IK session: a bidirectional stream answering each message with a
// solve warm-started from the previous answer. Reads, solves and writes
// strictly in turn (one operation in flight), so answers keep the order of
// the messages and the state needs no lock. Everything is freed in OnDone.
#pragma once

#include <cstdint>

#include "armature/engine/kinematics/ik_workspace.h"
#include "armature/v1/ik.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/ik/ik_convert.h"
#include "server/rpc/limits.h"
#include "server/rpc/session_admission.h"
#include "server/rpc/stream_admission.h"

namespace armature::server {

class IkSessionReactor final : public grpc::ServerBidiReactor<v1::IkSessionRequest, v1::SolveIkResponse> {
 public:
  // When `sessions` refuses the client a place, the stream ends at once
  // with its RESOURCE_EXHAUSTED.
  IkSessionReactor(grpc::CallbackServerContext* context, AssetStore& store, const Limits& limits,
                   SessionAdmission& sessions, StreamAdmission::Ticket stream);

  void OnReadDone(bool ok) override;
  void OnWriteDone(bool ok) override;
  void OnDone() override;

 private:
  void End(grpc::Status status);  // finishes the call (once)
  void ReadDone(bool ok);
  void WriteDone(bool ok);
  Status Answer();                // solves request_ into response_
  Status Start();   // the first message
  Status Update();  // a later one

  grpc::CallbackServerContext* context_;
  AssetStore& store_;
  const Limits& limits_;
  StreamAdmission::Ticket stream_;   // this call's place among the client's streams
  SessionAdmission::Ticket ticket_;  // this session's place

  v1::IkSessionRequest request_;
  v1::SolveIkResponse response_;
  uint64_t index_ = 0;  // messages answered
  IkCall call_;
  IkWorkspace workspace_;
  IkResult result_;
  PoseWorkspace pose_;
};

}  // namespace armature::server
