// The ImportAsset chunk protocol (server/assets/import_upload). Input: one
// byte choosing the upload limit (256 B << 0..7), then ImportAssetRequest
// messages, each preceded by its length as a varint, as a client streams
// them; a message that does not parse ends the stream. Every message is
// taken or refused with INVALID_ARGUMENT / RESOURCE_EXHAUSTED and a UTF-8
// message; an accepted upload holds exactly what was counted, under the
// limit, with the first message's header; it is then parsed as the store
// parses it (format detection, the glTF's resources).
#include <cstdint>
#include <cstdlib>
#include <string>

#include <google/protobuf/io/coded_stream.h>
#include <google/protobuf/io/zero_copy_stream_impl_lite.h>
#include <google/protobuf/stubs/logging.h>
#include <google/protobuf/util/delimited_message_util.h>

#include "armature/base/utf8.h"
#include "armature/engine/io/asset.h"
#include "fuzz_limits.h"
#include "server/assets/upload/import_upload.h"

namespace {

void CheckRefusal(const armature::Status& st) {
  using armature::StatusCode;
  if (st.code() != StatusCode::kInvalidArgument && st.code() != StatusCode::kResourceExhausted) std::abort();
  if (st.message().empty() || !armature::IsValidUtf8(st.message())) std::abort();
}

}  // namespace

// protobuf logs every string that is not UTF-8 it refuses to parse: quiet.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  google::protobuf::SetLogHandler(nullptr);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace armature;
  if (size == 0) return 0;
  const int64_t limit = int64_t{256} << (data[0] % 8);
  server::ImportUpload upload(limit);
  google::protobuf::io::ArrayInputStream stream(data + 1, static_cast<int>(size - 1));
  google::protobuf::io::CodedInputStream input(&stream);
  v1::ImportAssetRequest first;
  v1::ImportAssetRequest message;
  while (!input.ExpectAtEnd()) {
    bool clean_eof = false;
    if (!google::protobuf::util::ParseDelimitedFromCodedStream(&message, &input, &clean_eof)) break;
    if (upload.messages() == 0) first = message;
    if (Status st = upload.Add(message); !st.ok()) {
      CheckRefusal(st);
      return 0;
    }
    if (upload.received_bytes() > limit) std::abort();
  }
  const int64_t received = upload.received_bytes();
  const int64_t messages = upload.messages();
  auto import = std::move(upload).Finish();
  if (!import.ok()) {
    if (messages != 0) std::abort();
    CheckRefusal(import.status());
    return 0;
  }
  int64_t held = static_cast<int64_t>(import->bytes.size());
  for (const auto& [uri, bytes] : import->resources) {
    if (uri.empty()) std::abort();
    held += static_cast<int64_t>(uri.size() + bytes.size());
  }
  if (held != received || import->filename != first.filename() || import->name != first.name() ||
      import->format != first.format() || import->replace != first.replace())
    std::abort();

  auto format = DetectFormat(import->format, import->filename, import->bytes);
  if (!format.ok()) {
    if (!IsValidUtf8(format.status().message())) std::abort();
    return 0;
  }
  auto contents = ParseAsset(*format, import->bytes, "f", import->resources, fuzz::Limits());
  if (!contents.ok() && !IsValidUtf8(contents.status().message())) std::abort();
  return 0;
}
