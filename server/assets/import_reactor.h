// Receives an ImportAsset upload chunk by chunk, then hands it to the store.
#pragma once

#include <string>

#include "armature/v1/assets.grpc.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"

namespace armature::server {

class ImportReactor final : public grpc::ServerReadReactor<v1::ImportAssetRequest> {
 public:
  ImportReactor(grpc::CallbackServerContext* context, AssetStore& store, const Limits& limits,
                v1::ImportAssetResponse* response);

  void OnReadDone(bool ok) override;
  void OnDone() override { delete this; }

 private:
  void ReadDone(bool ok);
  void Complete();

  grpc::CallbackServerContext* context_;
  AssetStore& store_;
  const Limits& limits_;
  v1::ImportAssetResponse* response_;
  v1::ImportAssetRequest chunk_;
  ImportRequest import_;
  std::string* current_ = nullptr;  // the file the chunks go to: import_.bytes or a resource
  int64_t received_ = 0;
  bool first_ = true;
};

}  // namespace armature::server
