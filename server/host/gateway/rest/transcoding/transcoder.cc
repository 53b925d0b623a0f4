#include "server/host/gateway/rest/transcoding/transcoder.h"

#include <algorithm>
#include <cctype>
#include <cstdio>
#include <map>
#include <memory>

#include <nlohmann/json.hpp>

#include "server/host/gateway/rest/json/json_writer.h"
#include "server/host/gateway/rest/json/json_codec.h"

namespace armature::server::gateway {
namespace {

namespace pb = google::protobuf;
using nlohmann::json;

grpc::Status Invalid(const std::string& message) { return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, message); }

// Values for fields, as a JSON object protobuf's parser reads: every value is
// a JSON string, which the proto3 mapping accepts for numbers, bools and enums.
void Put(json& root, const FieldPath& path, const std::vector<std::string>& values) {
  json* node = &root;
  for (size_t i = 0; i + 1 < path.size(); ++i) node = &(*node)[path[i]->name()];
  json& leaf = (*node)[path.back()->name()];
  if (path.back()->is_repeated()) {
    for (const auto& v : values) leaf.push_back(v);
  } else {
    leaf = values.front();
  }
}

bool SameField(const FieldPath& a, const FieldPath& b) { return a == b; }

// JSON text of parameters; INVALID_ARGUMENT for values that are not UTF-8.
grpc::Status Dump(const json& j, const std::string& where, std::string* out) {
  try {
    *out = j.dump();
  } catch (const json::exception&) {
    return Invalid(where + ": values must be UTF-8 (percent-encode the bytes of UTF-8 text)");
  }
  return grpc::Status::OK;
}

}  // namespace

grpc::Status ParamsMessage(const HttpBinding& binding, const HttpRequestParts& http, pb::Message* params) {
  const pb::Descriptor* type = params->GetDescriptor();
  json from_path = json::object();
  for (size_t i = 0; i < http.path.size(); ++i) Put(from_path, binding.path_fields[i], {http.path[i].second});

  // Query parameters (then form fields) grouped by field, in first-seen order.
  std::vector<std::pair<FieldPath, std::vector<std::string>>> fields;
  std::map<std::string, size_t> index;
  auto take = [&](const std::string& kind, const std::string& name, const std::string& value) -> grpc::Status {
    const std::string where = kind + " '" + name + "'";
    const char* source = kind == "form field" ? "form" : "query";
    if (binding.body == "*")
      return Invalid(where + ": " + binding.http_method + " " + binding.path.text() +
                     " takes every field from the JSON body, none from the " + source);
    auto path = ResolveFieldPath(type, name);
    if (!path.ok()) return Invalid(kind + " " + path.status().message());
    const pb::FieldDescriptor* leaf = path->back();
    if (leaf->is_map()) return Invalid(where + ": map fields cannot be set from the " + source);
    if (leaf->type() == pb::FieldDescriptor::TYPE_MESSAGE)
      return Invalid(where + ": '" + leaf->name() + "' is a message; set its fields with dots, e.g. " + name + "." +
                     (leaf->message_type()->field_count() ? leaf->message_type()->field(0)->json_name() : "field"));
    for (const auto& bound : binding.path_fields)
      if (SameField(bound, *path)) return Invalid(where + ": the path already sets this field");
    if (!binding.body_field.empty() && path->front() == binding.body_field.front())
      return Invalid(where + ": the request body sets this field");
    const std::string key = ProtoNameOf(*path);
    auto [it, inserted] = index.emplace(key, fields.size());
    if (inserted) fields.emplace_back(std::move(*path), std::vector<std::string>{});
    auto& values = fields[it->second].second;
    values.push_back(value);
    if (!leaf->is_repeated() && values.size() > 1)
      return Invalid(where + ": given " + std::to_string(values.size()) + " times but it takes one value");
    return grpc::Status::OK;
  };
  for (const auto& [name, value] : http.query)
    if (auto st = take("query parameter", name, value); !st.ok()) return st;
  for (const auto& [name, value] : http.form)
    if (auto st = take("form field", name, value); !st.ok()) return st;
  json from_query = json::object();
  for (const auto& [path, values] : fields) Put(from_query, path, values);

  std::unique_ptr<pb::Message> part(params->New());
  std::string text;
  const std::string kind = http.form.empty() ? "query parameter" : "query parameter or form field";
  if (auto st = Dump(from_query, kind + "s", &text); !st.ok()) return st;
  if (auto st = JsonToMessage(text, part.get(), kind + "s", kind); !st.ok()) return st;
  params->MergeFrom(*part);
  // Path last, so it wins over anything else naming the same field.
  if (auto st = Dump(from_path, "path", &text); !st.ok()) return st;
  if (auto st = JsonToMessage(text, part.get(), "path", "path parameter"); !st.ok()) return st;
  params->MergeFrom(*part);
  return grpc::Status::OK;
}

namespace {

// One JSON value of the body into `message` according to the body rule.
grpc::Status BodyInto(const HttpBinding& binding, std::string_view body, const std::string& where,
                      pb::Message* message) {
  const std::string label = where + " field";
  if (binding.body == "*") return JsonToMessage(body, message, where, label);
  const pb::FieldDescriptor* field = binding.body_field.front();
  if (field->type() == pb::FieldDescriptor::TYPE_MESSAGE && !field->is_repeated())
    return JsonToMessage(body, message->GetReflection()->MutableMessage(message, field), where, label);
  // A scalar or repeated field: parse it as {"field": <body>}, once the body
  // is known to be one JSON value: '"x","name":"y"' would set other fields.
  if (auto st = CheckJsonSyntax(body, where); !st.ok()) return st;
  std::string wrapped = "{\"" + field->name() + "\":";
  wrapped.append(body.data(), body.size());
  wrapped += "}";
  std::unique_ptr<pb::Message> part(message->New());
  if (auto st = JsonToMessage(wrapped, part.get(), where, label); !st.ok()) return st;
  message->MergeFrom(*part);
  return grpc::Status::OK;
}

std::vector<std::string_view> Lines(std::string_view body) {
  std::vector<std::string_view> lines;
  size_t start = 0;
  while (start < body.size()) {
    const size_t end = std::min(body.find('\n', start), body.size());
    std::string_view line = body.substr(start, end - start);
    if (line.find_first_not_of(" \t\r") != std::string_view::npos) lines.push_back(line);
    start = end + 1;
  }
  return lines;
}

}  // namespace

bool IsNdjson(const std::string& content_type) {
  return content_type == "application/x-ndjson" || content_type == "application/ndjson" ||
         content_type == "application/jsonl" || content_type == "application/x-jsonlines";
}

bool IsJsonType(const std::string& content_type) {
  return content_type == "application/json" || IsNdjson(content_type) ||
         (content_type.size() > 5 && content_type.compare(content_type.size() - 5, 5, "+json") == 0);
}

bool IsProtobufType(const std::string& content_type) {
  return content_type == "application/x-protobuf" || content_type == "application/protobuf";
}

bool AcceptsProtobuf(const std::string& accept_header) {
  size_t start = 0;
  while (start <= accept_header.size()) {
    const size_t end = std::min(accept_header.find(',', start), accept_header.size());
    std::string item = accept_header.substr(start, end - start);
    start = end + 1;
    std::transform(item.begin(), item.end(), item.begin(), [](unsigned char c) { return std::tolower(c); });
    item.erase(std::remove_if(item.begin(), item.end(), [](unsigned char c) { return std::isspace(c); }), item.end());
    const size_t semicolon = item.find(';');
    if (!IsProtobufType(item.substr(0, semicolon))) continue;
    // "q=0", "q=0.0", "q=0.000" refuse the type.
    const size_t q = item.find(";q=", semicolon == std::string::npos ? item.size() : semicolon);
    if (q != std::string::npos && item.find_first_not_of("0.", q + 3) == std::string::npos) continue;
    return true;
  }
  return false;
}

bool IsRawBytesBody(const HttpBinding& binding, const std::string& content_type) {
  if (binding.body_field.empty() || content_type.empty() || IsJsonType(content_type) || IsProtobufType(content_type))
    return false;
  const pb::FieldDescriptor* f = binding.body_field.front();
  return f->type() == pb::FieldDescriptor::TYPE_BYTES && !f->is_repeated();
}

grpc::Status TranscodeRequest(const HttpBinding& binding, const pb::Message& prototype, const HttpRequestParts& http,
                              size_t chunk_bytes, std::vector<std::string>* requests) {
  std::unique_ptr<pb::Message> first(prototype.New());
  if (auto st = ParamsMessage(binding, http, first.get()); !st.ok()) return st;
  requests->clear();

  const bool has_body = http.body.find_first_not_of(" \t\r\n") != std::string_view::npos;
  if (binding.body.empty()) {
    if (has_body)
      return Invalid("request body: " + binding.http_method + " " + binding.path.text() +
                     " takes no body; send its fields as query parameters");
    requests->push_back(first->SerializeAsString());
    return grpc::Status::OK;
  }

  if (IsProtobufType(http.content_type)) {
    // The whole message's encoding; path and query fields win (merged last).
    std::unique_ptr<pb::Message> m(prototype.New());
    if (!m->ParseFromArray(http.body.data(), static_cast<int>(http.body.size())))
      return Invalid("request body: not a valid " + prototype.GetTypeName() + " encoding (Content-Type " +
                     http.content_type + ")");
    m->MergeFrom(*first);
    requests->push_back(m->SerializeAsString());
    return grpc::Status::OK;
  }
  const pb::FieldDescriptor* body_field = binding.body_field.empty() ? nullptr : binding.body_field.front();
  if (IsRawBytesBody(binding, http.content_type)) {
    // The raw body is the bytes field; a streaming RPC gets it in chunks.
    const size_t chunk = binding.client_streaming() && chunk_bytes > 0 ? chunk_bytes : http.body.size();
    size_t offset = 0;
    do {
      std::unique_ptr<pb::Message> m(offset == 0 ? first.release() : prototype.New());
      const size_t n = std::min(chunk, http.body.size() - offset);
      m->GetReflection()->SetString(m.get(), body_field, std::string(http.body.substr(offset, n)));
      requests->push_back(m->SerializeAsString());
      offset += n;
    } while (offset < http.body.size());
    return grpc::Status::OK;
  }
  if (binding.client_streaming() && IsNdjson(http.content_type)) {
    const auto lines = Lines(http.body);
    for (size_t i = 0; i < lines.size(); ++i) {
      std::unique_ptr<pb::Message> m(prototype.New());
      if (auto st = BodyInto(binding, lines[i], "request body line " + std::to_string(i + 1), m.get()); !st.ok())
        return st;
      if (i == 0) m->MergeFrom(*first);  // path and query fields go with the first message
      requests->push_back(m->SerializeAsString());
    }
    if (requests->empty()) requests->push_back(first->SerializeAsString());
    return grpc::Status::OK;
  }

  std::unique_ptr<pb::Message> m(prototype.New());
  if (has_body) {
    if (auto st = BodyInto(binding, http.body, "request body", m.get()); !st.ok()) return st;
  }
  m->MergeFrom(*first);
  requests->push_back(m->SerializeAsString());
  return grpc::Status::OK;
}

namespace {

std::string Mib(size_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%.1f MiB", static_cast<double>(bytes) / (1 << 20));
  return text;
}

}  // namespace

grpc::Status TranscodeResponse(const HttpBinding& binding, const pb::Message& prototype, std::string serialized,
                               size_t max_json_bytes, HttpBody* out) {
  std::unique_ptr<pb::Message> m(prototype.New());
  if (!m->ParseFromString(serialized))
    return grpc::Status(grpc::StatusCode::INTERNAL, "could not parse the " + prototype.GetTypeName() + " response");
  const size_t binary_bytes = serialized.size();
  std::string().swap(serialized);
  out->content_type = "application/json";
  out->content.clear();
  bool fits = true;
  if (binding.response_field.empty()) {
    fits = MessageToJson(*m, max_json_bytes, &out->content);
  } else {
    const pb::FieldDescriptor* field = binding.response_field.front();
    const pb::Reflection* r = m->GetReflection();
    if (field->type() == pb::FieldDescriptor::TYPE_BYTES && !field->is_repeated()) {
      out->content = r->GetString(*m, field);  // no larger than the message
      out->content_type = "application/octet-stream";
      // A message that says its bytes' type (MaterialImage) is served as that type.
      const pb::FieldDescriptor* mime = m->GetDescriptor()->FindFieldByName("mime_type");
      if (mime != nullptr && mime->type() == pb::FieldDescriptor::TYPE_STRING && !mime->is_repeated() &&
          !r->GetString(*m, mime).empty())
        out->content_type = r->GetString(*m, mime);
      return grpc::Status::OK;
    }
    fits = AppendFieldJson(*m, *field, max_json_bytes, &out->content);
  }
  if (fits) return grpc::Status::OK;
  std::string().swap(out->content);
  return grpc::Status(grpc::StatusCode::RESOURCE_EXHAUSTED,
                      "the answer as JSON passes the message limit of " + Mib(max_json_bytes) +
                          " (--max-message-mb); ask for less, or for its binary encoding (" + Mib(binary_bytes) +
                          "): header Accept: application/x-protobuf, or call over gRPC");
}

}  // namespace armature::server::gateway
