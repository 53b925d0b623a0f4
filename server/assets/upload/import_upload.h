// The ImportAsset chunk protocol, apart from gRPC so it can be tested and
// fuzzed alone: the first message names the upload (filename, name, format,
// replace) and starts the main file; a message with `resource` starts a
// further file; `data` appends to the current file. Everything the client
// sends (data and resource names) counts against the upload limit.
#pragma once

#include <cstdint>
#include <string>

#include "armature/base/status.h"
#include "armature/v1/assets.pb.h"
#include "server/assets/asset_store.h"

namespace armature::server {

class ImportUpload {
 public:
  explicit ImportUpload(int64_t max_upload_bytes) : max_bytes_(max_upload_bytes) {}

  // Takes the next message. RESOURCE_EXHAUSTED naming --max-upload-mb once
  // the upload outgrows the limit; INVALID_ARGUMENT for a header field after
  // the first message, a first message that starts a resource, or a
  // resource sent twice. After an error the upload is to be dropped.
  Status Add(const v1::ImportAssetRequest& message);

  // What the store imports. INVALID_ARGUMENT when no message came.
  StatusOr<ImportRequest> Finish() &&;

  int64_t received_bytes() const { return received_; }
  int64_t messages() const { return messages_; }

 private:
  int64_t max_bytes_;
  ImportRequest import_;
  std::string* current_ = &import_.bytes;  // the file data goes to: the main one or a resource
  int64_t received_ = 0;
  int64_t messages_ = 0;
};

}  // namespace armature::server
