#include "server/assets/import_reactor.h"

#include "armature/base/utf8.h"
#include "server/rpc/call_guard.h"
#include "server/rpc/grpc_status.h"
#include "server/assets/asset_convert.h"
#include "server/rpc/pose_convert.h"

namespace armature::server {

ImportReactor::ImportReactor(grpc::CallbackServerContext* context, AssetStore& store, const Limits& limits,
                             v1::ImportAssetResponse* response)
    : context_(context), store_(store), limits_(limits), response_(response), current_(&import_.bytes) {
  StartRead(&chunk_);
}

void ImportReactor::OnReadDone(bool ok) {
  GuardCallback(context_, "ImportAsset", [&] { ReadDone(ok); }, [this](grpc::Status st) { Finish(st); });
}

void ImportReactor::ReadDone(bool ok) {
  if (!ok) {  // the client finished sending
    Complete();
    return;
  }
  if (first_) {
    import_.filename = chunk_.filename();
    import_.name = chunk_.name();
    import_.format = chunk_.format();
    import_.replace = chunk_.replace();
    first_ = false;
  }
  if (!chunk_.resource().empty()) current_ = &import_.resources[chunk_.resource()];
  received_ += static_cast<int64_t>(chunk_.data().size());
  if (received_ > limits_.max_upload_bytes) {
    Finish(ToGrpcStatus(Status::ResourceExhausted(
        "upload exceeds the limit of " + std::to_string(limits_.max_upload_bytes) + " bytes (--max-upload-mb)")));
    return;
  }
  current_->append(chunk_.data());
  StartRead(&chunk_);
}

void ImportReactor::Complete() {
  // Not ok also when the call was cancelled (client gone, server shutting
  // down): a cut-short upload is not imported.
  if (context_->IsCancelled()) {
    Finish(grpc::Status(grpc::StatusCode::CANCELLED, "the upload was cancelled"));
    return;
  }
  if (first_) {
    Finish(ToGrpcStatus(Status::InvalidArgument("no data: the upload had no messages")));
    return;
  }
  auto stored = store_.Import(std::move(import_));
  if (stored.ok()) {
    *response_->mutable_asset() = AssetInfoOf(**stored);
    for (const std::string& w : (*stored)->contents.warnings) response_->add_warnings(IsValidUtf8(w) ? w : EscapeForMessage(w, 4096));
  }
  Finish(ToGrpcStatus(stored.status()));
}

}  // namespace armature::server
