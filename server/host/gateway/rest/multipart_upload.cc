#include "server/host/gateway/rest/multipart_upload.h"

#include <algorithm>
#include <cctype>
#include <iterator>
#include <memory>
#include <set>

#include <httplib.h>

#include "armature/base/utf8.h"

namespace armature::server::gateway {
namespace {

namespace pb = google::protobuf;

grpc::Status Invalid(const std::string& message) { return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, message); }

std::string Quoted(const std::string& s) {
  std::string out(1, '\'');  // appended, not "'" + …: GCC 12 warns falsely (-Wrestrict) on that
  out += EscapeForMessage(s, 200);
  out += '\'';
  return out;
}

std::string PartName(const FormPart& part) {
  return part.filename.empty() ? "form field " + Quoted(part.field)
                               : "form part " + Quoted(part.filename) + " (field " + Quoted(part.field) + ")";
}

bool IsGltfName(const std::string& filename) {
  constexpr std::string_view kExt = ".gltf";
  if (filename.size() < kExt.size()) return false;
  return std::equal(kExt.begin(), kExt.end(), filename.end() - kExt.size(),
                    [](char a, char b) { return a == std::tolower(static_cast<unsigned char>(b)); });
}

// `content` cut into chunks, the first into `head` (which may carry other fields).
void AppendChunks(std::unique_ptr<pb::Message> head, const pb::Message& prototype, const pb::FieldDescriptor* data,
                  const std::string& content, size_t chunk_bytes, std::vector<std::string>* requests) {
  const size_t chunk = chunk_bytes > 0 ? chunk_bytes : std::max<size_t>(content.size(), 1);
  size_t offset = 0;
  do {
    std::unique_ptr<pb::Message> m(offset == 0 ? head.release() : prototype.New());
    const size_t n = std::min(chunk, content.size() - offset);
    m->GetReflection()->SetString(m.get(), data, content.substr(offset, n));
    requests->push_back(m->SerializeAsString());
    offset += n;
  } while (offset < content.size());
}

// The part that is the main file: the one .gltf, else the only file.
grpc::Status MainPart(const std::vector<FormPart*>& files, FormPart** main) {
  if (files.empty())
    return Invalid(
        "multipart/form-data body: no file part; send the file as a part with a filename "
        "(a .gltf with the files it refers to, or one .glb, .bvh, .obj or .fbx)");
  std::vector<FormPart*> gltfs;
  std::copy_if(files.begin(), files.end(), std::back_inserter(gltfs),
               [](FormPart* p) { return IsGltfName(p->filename); });
  if (gltfs.size() > 1)
    return Invalid("form parts " + Quoted(gltfs[0]->filename) + " and " + Quoted(gltfs[1]->filename) +
                   " are both .gltf files: send one .gltf per import, with the files it refers to");
  if (gltfs.size() == 1) {
    *main = gltfs.front();
    return grpc::Status::OK;
  }
  if (files.size() == 1) {
    *main = files.front();
    return grpc::Status::OK;
  }
  std::string names;
  for (size_t i = 0; i < files.size() && i < 4; ++i) names += (i ? ", " : "") + Quoted(files[i]->filename);
  return Invalid(
      "multipart/form-data body: " + std::to_string(files.size()) + " file parts (" + names +
      (files.size() > 4 ? ", ..." : "") +
      ") and no .gltf among them: only a .gltf takes further files; send one file, or a .gltf and its files");
}

}  // namespace

bool AcceptsMultipartUpload(const HttpBinding& binding) {
  if (!binding.client_streaming() || binding.body_field.size() != 1) return false;
  const pb::FieldDescriptor* body = binding.body_field.front();
  const pb::Descriptor* type = binding.method->input_type();
  const pb::FieldDescriptor* filename = type->FindFieldByName("filename");
  const pb::FieldDescriptor* resource = type->FindFieldByName("resource");
  auto is_string = [](const pb::FieldDescriptor* f) {
    return f && f->type() == pb::FieldDescriptor::TYPE_STRING && !f->is_repeated();
  };
  return body->type() == pb::FieldDescriptor::TYPE_BYTES && !body->is_repeated() && is_string(filename) &&
         is_string(resource);
}

grpc::Status ReadMultipartForm(const httplib::ContentReader& reader, size_t limit_bytes, size_t drain_bytes,
                               std::vector<FormPart>* parts, bool* unread_left) {
  size_t total = 0;
  size_t dropped = 0;  // bytes read and dropped after the refusal
  grpc::Status refused;
  auto refuse = [&](grpc::Status status) {
    refused = std::move(status);
    std::vector<FormPart>().swap(*parts);  // the answer is decided: free what was read
    return true;
  };
  auto over_limit = [&] {
    return refuse(
        grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                     PartName(parts->back()) + ": the upload exceeds the limit of " + std::to_string(limit_bytes) +
                         " bytes (--max-upload-mb) at this part; every part, filename and field name counts"));
  };
  const bool complete = reader(
      [&](const httplib::MultipartFormData& header) {
        if (!refused.ok()) return (dropped += header.name.size() + header.filename.size()) <= drain_bytes;
        if (parts->size() >= kMaxFormParts)
          return refuse(
              grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                           "multipart/form-data body: more than " + std::to_string(kMaxFormParts) + " parts"));
        parts->push_back(FormPart{header.name, header.filename, {}});
        total += header.name.size() + header.filename.size();
        return total <= limit_bytes || over_limit();
      },
      [&](const char* data, size_t n) {
        if (!refused.ok()) return (dropped += n) <= drain_bytes;
        if (parts->empty()) return false;  // the parser announces a part before its data
        total += n;
        if (total > limit_bytes) return over_limit();
        parts->back().content.append(data, n);
        return true;
      });
  *unread_left = !complete;
  if (!refused.ok()) return refused;
  if (!complete)
    return Invalid(
        "multipart/form-data body: malformed (no or a wrong boundary, a part without headers, or cut short)");
  return grpc::Status::OK;
}

grpc::Status TranscodeMultipartUpload(const HttpBinding& binding, const pb::Message& prototype,
                                      const HttpRequestParts& http, std::vector<FormPart> parts, size_t chunk_bytes,
                                      std::vector<std::string>* requests) {
  const pb::Descriptor* type = prototype.GetDescriptor();
  const pb::FieldDescriptor* filename = type->FindFieldByName("filename");
  const pb::FieldDescriptor* resource = type->FindFieldByName("resource");
  const pb::FieldDescriptor* data = binding.body_field.front();

  HttpRequestParts fields;
  fields.path = http.path;
  fields.query = http.query;
  std::vector<FormPart*> files;
  std::set<std::string> file_names;
  for (FormPart& part : parts) {
    if (part.filename.empty()) {
      fields.form.emplace_back(part.field, std::move(part.content));
      continue;
    }
    if (!file_names.insert(part.filename).second)
      return Invalid("form parts: two files are named " + Quoted(part.filename) +
                     "; each file part needs its own filename, the name the .gltf's uri gives it");
    files.push_back(&part);
  }
  FormPart* main = nullptr;
  if (auto st = MainPart(files, &main); !st.ok()) return st;

  std::unique_ptr<pb::Message> first(prototype.New());
  if (auto st = ParamsMessage(binding, fields, first.get()); !st.ok()) return st;
  const pb::Reflection* reflection = first->GetReflection();
  if (!reflection->GetString(*first, filename).empty())
    return Invalid("'" + filename->name() + "': the main file part's filename gives it (here " +
                   Quoted(main->filename) + "); set no such query parameter or form field");
  if (!reflection->GetString(*first, resource).empty())
    return Invalid("'" + resource->name() +
                   "': the file parts besides the main one are the resources, each named "
                   "by its filename; set no such query parameter or form field");
  reflection->SetString(first.get(), filename, main->filename);

  requests->clear();
  AppendChunks(std::move(first), prototype, data, main->content, chunk_bytes, requests);
  std::string().swap(main->content);  // the messages hold it now
  for (FormPart* part : files) {
    if (part == main) continue;
    std::unique_ptr<pb::Message> head(prototype.New());
    head->GetReflection()->SetString(head.get(), resource, part->filename);
    AppendChunks(std::move(head), prototype, data, part->content, chunk_bytes, requests);
    std::string().swap(part->content);
  }
  return grpc::Status::OK;
}

}  // namespace armature::server::gateway
