#include "server/assets/upload/import_upload.h"

#include "armature/base/utf8.h"
#include "armature/engine/anim/compression/error_bound.h"

namespace armature::server {
namespace {

// The header field a later message sets, or nullptr.
const char* HeaderFieldOf(const v1::ImportAssetRequest& m) {
  if (!m.filename().empty()) return "filename";
  if (!m.name().empty()) return "name";
  if (!m.format().empty()) return "format";
  if (m.replace()) return "replace";
  if (!m.precision().empty()) return "precision";
  return nullptr;
}

}  // namespace

Status ImportUpload::Add(const v1::ImportAssetRequest& message) {
  const int64_t index = ++messages_;
  // Resource names are kept as map keys: they count like data.
  received_ += static_cast<int64_t>(message.data().size() + message.resource().size());
  if (received_ > max_bytes_)
    return Status::ResourceExhausted("upload exceeds the limit of " + std::to_string(max_bytes_) +
                                     " bytes (--max-upload-mb)");
  if (index == 1) {
    if (!message.resource().empty())
      return Status::InvalidArgument("message 1: starts resource '" + EscapeForMessage(message.resource(), 256) +
                                     "', but the first message starts the main file (send resources after it)");
    import_.filename = message.filename();
    import_.name = message.name();
    import_.format = message.format();
    import_.replace = message.replace();
    // Refused before the file's bytes arrive; the store reads it again against its default.
    ARMATURE_RETURN_IF_ERROR(ParseClipPrecision(message.precision(), "precision").status());
    import_.precision = message.precision();
  } else if (const char* field = HeaderFieldOf(message)) {
    return Status::InvalidArgument("message " + std::to_string(index) + ": " + field +
                                   " belongs in the first message only");
  }
  if (!message.resource().empty()) {
    auto [it, fresh] = import_.resources.try_emplace(message.resource());
    if (!fresh)
      return Status::InvalidArgument("message " + std::to_string(index) + ": resource '" +
                                     EscapeForMessage(message.resource(), 256) + "' was already sent");
    current_ = &it->second;
  }
  current_->append(message.data());
  return Status::Ok();
}

StatusOr<ImportRequest> ImportUpload::Finish() && {
  if (messages_ == 0) return Status::InvalidArgument("no data: the upload had no messages");
  return std::move(import_);
}

}  // namespace armature::server
