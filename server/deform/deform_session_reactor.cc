#include "server/deform/deform_session_reactor.h"

#include <optional>
#include <string>
#include <vector>

#include "server/deform/mesh_deformer.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/grpc_status.h"
#include "server/rpc/pose_convert.h"

namespace armature::server {
namespace {

// One drag session: reads a message, answers it, reads the next. The solver
// (and its factorization) lives exactly as long as the call.
class DeformSessionReactor final : public grpc::ServerBidiReactor<v1::DeformSessionRequest, v1::DeformResponse> {
 public:
  DeformSessionReactor(grpc::CallbackServerContext* context, AssetStore& store, const Limits& limits,
                       SessionAdmission& sessions, StreamAdmission::Ticket stream, ElasticThreadPool& setups)
      : context_(context), store_(store), limits_(limits), setups_(setups), stream_(std::move(stream)) {
    auto ticket = sessions.Admit(*context, SessionKind::kDeform);
    if (!ticket.ok()) {
      Finish(ToGrpcStatus(ticket.status()));
      return;
    }
    ticket_ = std::move(*ticket);
    StartRead(&request_);
  }

  void OnReadDone(bool ok) override {
    GuardCallback(context_, "DeformSession", [&] { ReadDone(ok); }, [this](grpc::Status st) { EndWith(st); });
  }

  void ReadDone(bool ok) {
    if (!ok) {  // the client closed its side: the session ends normally
      End(Status::Ok());
      return;
    }
    if (!deformer_) {  // the setup factors: off the callback thread
      setups_.Enqueue([this] {
        GuardCallback(context_, "DeformSession", [&] { Answer(); }, [this](grpc::Status st) { EndWith(st); });
      });
      return;
    }
    Answer();  // a move is a back-substitution: milliseconds
  }

  void Answer() {
    response_.Clear();
    const Status st = Handle();
    if (!st.ok()) {
      End(st);
      return;
    }
    StartWrite(&response_);
  }

  void OnWriteDone(bool ok) override {
    if (!ok) {
      End(Status::Cancelled("the client went away"));
      return;
    }
    StartRead(&request_);
  }

  // Ends the call after an exception (call_guard.h): nothing here may throw.
  void EndWith(const grpc::Status& status) noexcept {
    deformer_.reset();
    ticket_.Release();
    Finish(status);
  }

  void OnDone() override { delete this; }  // the ticket, if still held (cancelled mid-solve), goes with it

 private:
  // Frees the factorization and the session slot before the client sees the
  // end, so a client that closes a session can open the next one at once.
  void End(const Status& status) {
    deformer_.reset();
    ticket_.Release();
    Finish(ToGrpcStatus(status));
  }

  Status Handle() {
    if (!deformer_) {
      if (!request_.has_start())
        return Status::InvalidArgument("start: the first message of a session must be `start` (mesh and constraints)");
      const auto& start = request_.start();
      std::vector<uint32_t> handles(start.handle_indices().begin(), start.handle_indices().end());
      auto d = MeshDeformer::Create(*store_.Snapshot(), limits_, start.setup(), std::move(handles));
      if (!d.ok()) return d.status();
      deformer_.emplace(std::move(*d));
      // The setup's answer: the handles at rest, i.e. the rest shape.
      ARMATURE_RETURN_IF_ERROR(deformer_->Solve(deformer_->RestHandlePositions(), "start", &response_));
      response_.set_index(0);
      return Status::Ok();
    }
    if (!request_.has_move())
      return Status::InvalidArgument("move: messages after the first must be `move` (handle positions)");
    ++moves_;
    ARMATURE_RETURN_IF_ERROR(
        deformer_->Solve(AsSpan(request_.move().positions()), "move[" + std::to_string(moves_) + "].positions", &response_));
    response_.set_index(moves_);
    return Status::Ok();
  }

  grpc::CallbackServerContext* context_;
  AssetStore& store_;
  const Limits& limits_;
  ElasticThreadPool& setups_;
  StreamAdmission::Ticket stream_;   // this call's place among the client's streams
  SessionAdmission::Ticket ticket_;  // this session's place
  uint64_t moves_ = 0;
  std::optional<MeshDeformer> deformer_;
  v1::DeformSessionRequest request_;
  v1::DeformResponse response_;
};

}  // namespace

grpc::ServerBidiReactor<v1::DeformSessionRequest, v1::DeformResponse>* NewDeformSession(
    grpc::CallbackServerContext* context, AssetStore& store, const Limits& limits, SessionAdmission& sessions,
    StreamAdmission::Ticket stream, ElasticThreadPool& setups) {
  return new DeformSessionReactor(context, store, limits, sessions, std::move(stream), setups);
}

}  // namespace armature::server
