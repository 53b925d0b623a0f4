// Receives an ImportAsset upload chunk by chunk (ImportUpload assembles it),
// then hands it to the store.
#pragma once

#include <string>

#include "armature/v1/assets.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/assets/upload/import_upload.h"
#include "server/rpc/streams/admission_ticket.h"
#include "server/rpc/limits.h"

namespace armature::server {

class ImportReactor final : public grpc::ServerReadReactor<v1::ImportAssetRequest> {
 public:
  // `admitted`: the upload's place (UploadAdmission), or why there is none
  // (then the call is answered with it before anything is read).
  ImportReactor(grpc::CallbackServerContext* context, AssetStore& store, const Limits& limits,
                StatusOr<AdmissionTicket> admitted, v1::ImportAssetResponse* response);

  void OnReadDone(bool ok) override;
  void OnDone() override { delete this; }

 private:
  void ReadDone(bool ok);
  void Complete();
  // Gives the upload's place back, then answers: a client that has its answer
  // may upload again at once, even before gRPC calls OnDone.
  void End(const grpc::Status& status);

  grpc::CallbackServerContext* context_;
  AssetStore& store_;
  v1::ImportAssetResponse* response_;
  v1::ImportAssetRequest chunk_;
  ImportUpload upload_;
  StatusOr<AdmissionTicket> admitted_;
};

}  // namespace armature::server
