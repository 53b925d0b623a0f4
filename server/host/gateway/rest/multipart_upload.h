// multipart/form-data uploads, the way browsers send files, for RPCs that
// take a file and the further files it refers to (ImportAsset): a client-
// streaming RPC whose body is a bytes field and whose request has `filename`
// and `resource` fields. The form's one .gltf part (or its only file part) is
// the main file; every other file part is a resource named by its part's
// filename, the name the .gltf's uris use; text fields set request fields
// the way query parameters do (`name`, `format`, `replace`). The messages
// follow ImportAsset's chunk protocol (server/assets/upload/import_upload.h), so
// the upload takes the same path, limits and checks as over gRPC.
#pragma once

#include <string>
#include <vector>

#include <google/protobuf/message.h>
#include <grpcpp/grpcpp.h>

#include "server/host/gateway/rest/transcoding/http_rule.h"
#include "server/host/gateway/rest/transcoding/transcoder.h"

namespace httplib {
class ContentReader;
}

namespace armature::server::gateway {

struct FormPart {
  std::string field;     // the form field's name
  std::string filename;  // empty for a text field
  std::string content;
};

// At most this many parts in one form (cpp-httplib's own cap for forms it parses).
inline constexpr size_t kMaxFormParts = 1024;

// True when `binding` takes a multipart/form-data upload.
bool AcceptsMultipartUpload(const HttpBinding& binding);

// Reads the form's parts. RESOURCE_EXHAUSTED naming the part once the
// contents, filenames and field names of the parts together exceed
// `limit_bytes` (--max-upload-mb) or the parts outnumber kMaxFormParts;
// INVALID_ARGUMENT for a body that is not a well-formed form. A refused
// form is still read and dropped for up to `drain_bytes` more, so the
// connection stays in step; `*unread_left` tells whether the body was left
// partly unread (then the connection must close).
grpc::Status ReadMultipartForm(const httplib::ContentReader& reader, size_t limit_bytes, size_t drain_bytes,
                               std::vector<FormPart>* parts, bool* unread_left);

// The serialized request messages: the first carries the path, query and form
// fields, the main part's filename and its first chunk; each resource then
// starts with a message naming it. INVALID_ARGUMENT for a form without a file,
// with two .gltf parts, several files but no .gltf, two files of one name, or a
// text field that sets what the parts set.
grpc::Status TranscodeMultipartUpload(const HttpBinding& binding, const google::protobuf::Message& prototype,
                                      const HttpRequestParts& http, std::vector<FormPart> parts, size_t chunk_bytes,
                                      std::vector<std::string>* requests);

}  // namespace armature::server::gateway
