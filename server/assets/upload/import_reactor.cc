#include "server/assets/upload/import_reactor.h"

#include "armature/base/utf8.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/grpc_status.h"
#include "server/assets/asset_convert.h"
#include "server/rpc/convert/pose_convert.h"

namespace armature::server {

ImportReactor::ImportReactor(grpc::CallbackServerContext* context, AssetStore& store, const Limits& limits,
                             StatusOr<AdmissionTicket> admitted, v1::ImportAssetResponse* response)
    : context_(context),
      store_(store),
      response_(response),
      upload_(limits.max_upload_bytes),
      admitted_(std::move(admitted)) {
  if (!admitted_.ok()) {
    Finish(ToGrpcStatus(admitted_.status()));
    return;
  }
  StartRead(&chunk_);
}

void ImportReactor::OnReadDone(bool ok) {
  GuardCallback(
      context_, "ImportAsset", [&] { ReadDone(ok); }, [this](grpc::Status st) { End(st); });
}

void ImportReactor::ReadDone(bool ok) {
  if (!ok) {  // the client finished sending
    Complete();
    return;
  }
  if (Status st = upload_.Add(chunk_); !st.ok()) {
    End(ToGrpcStatus(st));
    return;
  }
  StartRead(&chunk_);
}

void ImportReactor::Complete() {
  // Not ok also when the call was cancelled (client gone, server shutting
  // down): a cut-short upload is not imported.
  if (context_->IsCancelled()) {
    End(grpc::Status(grpc::StatusCode::CANCELLED, "the upload was cancelled"));
    return;
  }
  auto import = std::move(upload_).Finish();
  if (!import.ok()) {
    End(ToGrpcStatus(import.status()));
    return;
  }
  auto stored = store_.Import(std::move(*import));
  if (stored.ok()) {
    *response_->mutable_asset() = AssetInfoOf(**stored);
    for (const std::string& w : (*stored)->contents.warnings)
      response_->add_warnings(IsValidUtf8(w) ? w : EscapeForMessage(w, 4096));
  }
  End(ToGrpcStatus(stored.status()));
}

void ImportReactor::End(const grpc::Status& status) {
  if (admitted_.ok()) admitted_->Release();
  Finish(status);
}

}  // namespace armature::server
