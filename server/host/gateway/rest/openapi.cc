#include "server/host/gateway/rest/openapi.h"

#include <algorithm>
#include <cctype>
#include <set>

#include "server/host/gateway/rest/multipart_upload.h"

namespace armature::server::gateway {
namespace {

namespace pb = google::protobuf;
using nlohmann::json;

std::string Ref(const std::string& full_name) { return "#/components/schemas/" + full_name; }

// Collects the schemas of every message and enum an operation refers to.
class SchemaBuilder {
 public:
  json MessageRef(const pb::Descriptor* d) {
    if (auto wkt = WellKnown(d); !wkt.is_null()) return wkt;
    Add(d);
    return {{"$ref", Ref(d->full_name())}};
  }

  json FieldSchema(const pb::FieldDescriptor* f) {
    if (f->is_map()) {
      return {{"type", "object"}, {"additionalProperties", SingleSchema(f->message_type()->map_value())}};
    }
    json s = SingleSchema(f);
    if (f->is_repeated()) return {{"type", "array"}, {"items", s}};
    return s;
  }

  json SingleSchema(const pb::FieldDescriptor* f) {
    using T = pb::FieldDescriptor;
    switch (f->type()) {
      case T::TYPE_DOUBLE: return {{"type", "number"}, {"format", "double"}};
      case T::TYPE_FLOAT: return {{"type", "number"}, {"format", "float"}};
      case T::TYPE_INT32:
      case T::TYPE_SINT32:
      case T::TYPE_SFIXED32: return {{"type", "integer"}, {"format", "int32"}};
      case T::TYPE_UINT32:
      case T::TYPE_FIXED32: return {{"type", "integer"}, {"format", "int64"}, {"minimum", 0}};
      // The proto3 JSON mapping writes 64-bit integers as strings.
      case T::TYPE_INT64:
      case T::TYPE_SINT64:
      case T::TYPE_SFIXED64: return {{"type", "string"}, {"format", "int64"}};
      case T::TYPE_UINT64:
      case T::TYPE_FIXED64: return {{"type", "string"}, {"format", "uint64"}};
      case T::TYPE_BOOL: return {{"type", "boolean"}};
      case T::TYPE_STRING: return {{"type", "string"}};
      case T::TYPE_BYTES: return {{"type", "string"}, {"format", "byte"}};
      case T::TYPE_ENUM: Add(f->enum_type()); return {{"$ref", Ref(f->enum_type()->full_name())}};
      case T::TYPE_MESSAGE:
      case T::TYPE_GROUP: return MessageRef(f->message_type());
    }
    return json::object();
  }

  json schemas() const { return schemas_; }

 private:
  static json WellKnown(const pb::Descriptor* d) {
    const std::string& n = d->full_name();
    if (n.rfind("google.protobuf.", 0) != 0) return nullptr;
    if (n == "google.protobuf.Timestamp") return {{"type", "string"}, {"format", "date-time"}};
    if (n == "google.protobuf.Duration" || n == "google.protobuf.FieldMask") return {{"type", "string"}};
    if (n == "google.protobuf.Struct" || n == "google.protobuf.Empty" || n == "google.protobuf.Any")
      return {{"type", "object"}};
    if (n == "google.protobuf.Value") return json::object();
    if (n == "google.protobuf.ListValue") return {{"type", "array"}, {"items", json::object()}};
    if (n.size() > 5 && n.compare(n.size() - 5, 5, "Value") == 0 && d->field_count() == 1) {  // wrappers
      SchemaBuilder scalar;
      json s = scalar.SingleSchema(d->field(0));
      s["nullable"] = true;
      return s;
    }
    return nullptr;
  }

  void Add(const pb::EnumDescriptor* e) {
    if (schemas_.contains(e->full_name())) return;
    json values = json::array();
    for (int i = 0; i < e->value_count(); ++i) values.push_back(e->value(i)->name());
    schemas_[e->full_name()] = {{"type", "string"}, {"enum", values}, {"title", e->name()}};
  }

  void Add(const pb::Descriptor* d) {
    if (schemas_.contains(d->full_name())) return;
    schemas_[d->full_name()] = json::object();  // placeholder: breaks recursion
    json properties = json::object();
    for (int i = 0; i < d->field_count(); ++i) properties[d->field(i)->json_name()] = FieldSchema(d->field(i));
    schemas_[d->full_name()] = {{"type", "object"}, {"title", d->name()}, {"properties", properties}};
  }

  json schemas_ = json::object();
};

bool Contains(const std::vector<FieldPath>& paths, const FieldPath& p) {
  return std::find(paths.begin(), paths.end(), p) != paths.end();
}

// Query parameters: every scalar leaf not set by the path or the body,
// reached through singular message fields (dotted names).
void QueryParameters(const pb::Descriptor* d, const HttpBinding& b, FieldPath prefix,
                     std::set<const pb::Descriptor*> seen, SchemaBuilder& schemas, json& out) {
  if (!seen.insert(d).second) return;
  for (int i = 0; i < d->field_count(); ++i) {
    const pb::FieldDescriptor* f = d->field(i);
    FieldPath path = prefix;
    path.push_back(f);
    if (Contains(b.path_fields, path) || (!b.body_field.empty() && path.front() == b.body_field.front())) continue;
    if (f->is_map()) continue;
    if (f->type() == pb::FieldDescriptor::TYPE_MESSAGE) {
      if (!f->is_repeated()) QueryParameters(f->message_type(), b, path, seen, schemas, out);
      continue;
    }
    std::string name;
    for (const auto* p : path) name += (name.empty() ? "" : ".") + p->json_name();
    json param = {{"name", name}, {"in", "query"}, {"required", false}, {"schema", schemas.FieldSchema(f)}};
    if (f->is_repeated()) param["explode"] = true;
    out.push_back(param);
  }
}

std::string Lower(std::string s) {
  for (auto& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

json Operation(const HttpBinding& b, SchemaBuilder& schemas) {
  const pb::MethodDescriptor* m = b.method;
  std::string kind = m->client_streaming() && m->server_streaming() ? "bidirectional-streaming"
                     : m->client_streaming()                        ? "client-streaming"
                     : m->server_streaming()                        ? "server-streaming"
                                                                    : "unary";
  std::string description = "gRPC " + m->full_name() + " (" + kind + ").";
  if (m->server_streaming())
    description += " The response is a text/event-stream: each `data:` event is one JSON " + m->output_type()->name() +
                   ", and a final `event: status` carries {code, message, details} (code 0: the stream ended well).";
  if (m->client_streaming()) description += " An application/x-ndjson body sends one request message per line.";
  json op = {{"operationId", m->service()->name() + "_" + m->name() + (b.index ? "_" + std::to_string(b.index) : "")},
             {"summary", m->service()->name() + "." + m->name()},
             {"description", description},
             {"tags", json::array({m->service()->name()})}};

  json parameters = json::array();
  const auto vars = b.path.variables();
  for (size_t i = 0; i < vars.size(); ++i)
    parameters.push_back({{"name", vars[i]},
                          {"in", "path"},
                          {"required", true},
                          {"schema", schemas.FieldSchema(b.path_fields[i].back())}});
  if (b.body != "*") QueryParameters(m->input_type(), b, {}, {}, schemas, parameters);
  if (!parameters.empty()) op["parameters"] = parameters;

  if (!b.body.empty()) {
    json content = json::object();
    if (b.body == "*") {
      content["application/json"] = {{"schema", schemas.MessageRef(m->input_type())}};
    } else {
      const pb::FieldDescriptor* f = b.body_field.front();
      if (f->type() == pb::FieldDescriptor::TYPE_BYTES && !f->is_repeated())
        content["application/octet-stream"] = {{"schema", {{"type", "string"}, {"format", "binary"}}}};
      content["application/json"] = {{"schema", schemas.FieldSchema(f)}};
    }
    if (m->client_streaming()) content["application/x-ndjson"] = content["application/json"];
    if (AcceptsMultipartUpload(b))  // the main file and its resources as file parts (multipart_upload.h)
      content["multipart/form-data"] = {
          {"schema",
           {{"type", "object"},
            {"properties",
             {{"files", {{"type", "array"}, {"items", {{"type", "string"}, {"format", "binary"}}}}},
              {"name", {{"type", "string"}}}}}}}};
    op["requestBody"] = {{"required", b.body != "*"}, {"content", content}};
  }

  json response_schema = schemas.MessageRef(m->output_type());
  std::string media = m->server_streaming() ? "text/event-stream" : "application/json";
  if (!b.response_field.empty()) {
    const pb::FieldDescriptor* f = b.response_field.front();
    const bool raw = f->type() == pb::FieldDescriptor::TYPE_BYTES && !f->is_repeated();
    response_schema = raw ? json{{"type", "string"}, {"format", "binary"}} : schemas.FieldSchema(f);
    if (raw) media = "application/octet-stream";
  }
  op["responses"] = {{"200", {{"description", "OK"}, {"content", {{media, {{"schema", response_schema}}}}}}},
                     {"default",
                      {{"description", "An error: the HTTP status follows the gRPC code"},
                       {"content", {{"application/json", {{"schema", {{"$ref", Ref("Status")}}}}}}}}}};
  return op;
}

}  // namespace

json OpenApiDocument(const std::vector<HttpBinding>& bindings, const OpenApiInfo& info) {
  SchemaBuilder schemas;
  json paths = json::object();
  static const std::set<std::string> kOpenApiMethods = {"get", "put", "post", "delete", "patch", "head", "options"};
  for (const HttpBinding& b : bindings) {
    const std::string method = Lower(b.http_method);
    if (kOpenApiMethods.count(method)) paths[b.path.Simplified()][method] = Operation(b, schemas);
  }
  json components = schemas.schemas();
  components["Status"] = {
      {"type", "object"},
      {"title", "Status"},
      {"properties",
       {{"code", {{"type", "integer"}, {"format", "int32"}, {"description", "the gRPC status code"}}},
        {"message", {{"type", "string"}}},
        {"details", {{"type", "array"}, {"items", {{"type", "object"}}}}}}}};
  json doc = {{"openapi", "3.0.3"},
              {"info", {{"title", info.title}, {"version", info.version}}},
              {"paths", paths},
              {"components", {{"schemas", components}}}};
  if (!info.description.empty()) doc["info"]["description"] = info.description;
  return doc;
}

}  // namespace armature::server::gateway
