// The REST gateway's request side as Gateway::Handle drives it: the request
// target is split by the path templates, its query by cpp-httplib, and the
// path variables, query and body become request messages (transcoder,
// json_codec) for the API's real routes. Input:
//   "<METHOD> <target>\n<content type>\n<body>"
// A target no route matches still reaches the transcoder: a route picked by
// the input's size, its variables bound to the last path segment.
// Every request gets messages that parse back, or INVALID_ARGUMENT with a
// message the gateway can print as JSON; a body bound to a field sets only
// that field; a raw body is chunked losslessly.
// The body also goes through the response side as a serialized response.
#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <string>
#include <string_view>
#include <vector>

#include <google/protobuf/stubs/logging.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "api_bindings.h"
#include "server/host/gateway/common/error_mapping.h"
#include "server/host/gateway/rest/transcoding/http_rule.h"
#include "server/host/gateway/rest/transcoding/transcoder.h"

namespace {

namespace gw = armature::server::gateway;
namespace pb = google::protobuf;

const std::vector<gw::HttpBinding>& Bindings() { return armature::fuzz::ApiBindings(); }

const pb::Message& Prototype(const pb::Descriptor* type) {
  return *pb::MessageFactory::generated_factory()->GetPrototype(type);
}

std::string_view NextLine(std::string_view& in) {
  const size_t eol = in.find('\n');
  const std::string_view line = in.substr(0, eol);
  in = eol == std::string_view::npos ? std::string_view() : in.substr(eol + 1);
  return line;
}

// The route Gateway::Match picks: among the most specific templates that
// match, whatever their method, the one for `method`; else nullptr.
const gw::HttpBinding* Route(const std::string& method, const gw::RequestPath& path, gw::PathBindings* vars) {
  int best = -1;
  gw::PathBindings found;
  for (const auto& b : Bindings())
    if (b.path.Match(path, &found)) best = std::max(best, b.path.specificity());
  for (const auto& b : Bindings())
    if (b.http_method == method && b.path.specificity() == best && b.path.Match(path, vars)) return &b;
  return nullptr;
}

void CheckError(const grpc::Status& st) {
  if (st.error_code() != grpc::StatusCode::INVALID_ARGUMENT || st.error_message().empty()) std::abort();
  // What the client reads: the gateway's error JSON must print and parse.
  const auto json = nlohmann::json::parse(gw::ErrorJson(st.error_code(), st.error_message()));
  if (!json["message"].is_string()) std::abort();
}

}  // namespace

// protobuf logs every string that is not UTF-8 it refuses to parse: quiet.
extern "C" int LLVMFuzzerInitialize(int*, char***) {
  google::protobuf::SetLogHandler(nullptr);
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  std::string_view in(reinterpret_cast<const char*>(data), size);
  const std::string_view request_line = NextLine(in);
  const std::string_view content_type = NextLine(in);
  const size_t space = request_line.find(' ');
  if (space == std::string_view::npos) return 0;
  const std::string method(request_line.substr(0, space));
  const std::string target(request_line.substr(space + 1));

  auto path = gw::RequestPath::Parse(target);
  if (!path.ok()) return 0;
  gw::HttpRequestParts http;
  const gw::HttpBinding* binding = Route(method, *path, &http.path);
  if (binding == nullptr) {
    binding = &Bindings()[size % Bindings().size()];
    http.path.clear();
    for (const auto& var : binding->path.variables()) http.path.emplace_back(var, path->segments.back());
  }
  if (const size_t q = target.find('?'); q != std::string::npos) {
    httplib::Params params;
    httplib::detail::parse_query_text(target.substr(q + 1, target.find('#', q) - q - 1), params);
    for (const auto& [k, v] : params) http.query.emplace_back(k, v);
  }
  http.content_type = std::string(content_type);
  http.body = in;

  const pb::Message& prototype = Prototype(binding->method->input_type());
  constexpr size_t kChunk = 7;  // small, so raw bodies span several messages
  std::vector<std::string> requests;
  const grpc::Status st = gw::TranscodeRequest(*binding, prototype, http, kChunk, &requests);
  if (!st.ok()) {
    CheckError(st);
  } else {
    if (requests.empty()) std::abort();
    // A protobuf body is one request message, whatever the RPC's kind.
    if (gw::IsProtobufType(http.content_type) && requests.size() != 1) std::abort();
    // A body rule naming a field: the body sets that field and nothing else,
    // so apart from it the first message is what path and query give, and
    // later ones are empty. (A protobuf body is the whole message instead.)
    std::vector<std::string> params;
    const bool field_body = !binding->body_field.empty() && !gw::IsProtobufType(http.content_type);
    if (field_body) {
      gw::HttpRequestParts no_body = http;
      no_body.body = {};
      if (!gw::TranscodeRequest(*binding, prototype, no_body, kChunk, &params).ok() || params.size() != 1) std::abort();
    }
    std::string raw;
    for (size_t i = 0; i < requests.size(); ++i) {
      std::unique_ptr<pb::Message> m(prototype.New());
      if (!m->ParseFromString(requests[i])) std::abort();
      if (!field_body) continue;
      const pb::FieldDescriptor* field = binding->body_field.front();
      if (gw::IsRawBytesBody(*binding, http.content_type)) raw += m->GetReflection()->GetString(*m, field);
      m->GetReflection()->ClearField(m.get(), field);
      if (m->SerializeAsString() != (i == 0 ? params[0] : std::string())) std::abort();
    }
    if (gw::IsRawBytesBody(*binding, http.content_type) && raw != in) std::abort();
  }

  gw::HttpBody out;
  const pb::Message& response = Prototype(binding->method->output_type());
  if (gw::TranscodeResponse(*binding, response, std::string(in), 64u << 20, &out).ok() &&
      out.content_type == "application/json")
    (void)nlohmann::json::parse(out.content);
  return 0;
}
