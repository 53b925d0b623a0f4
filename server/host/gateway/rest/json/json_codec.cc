#include "server/host/gateway/rest/json/json_codec.h"

#include <algorithm>
#include <limits>

#include <google/protobuf/descriptor.h>
#include <google/protobuf/util/json_util.h>
#include <nlohmann/json.hpp>

#include "server/host/gateway/rest/json/json_writer.h"

namespace armature::server::gateway {
namespace {

// protobuf says "(times[1]): invalid value …"; we say "<label> 'times[1]': invalid value …".
std::string NameTheField(const std::string& message, const std::string& where, const std::string& label) {
  const size_t close = message.find("): ");
  if (message.empty() || message[0] != '(' || close == std::string::npos) return where + ": " + message;
  return label + " '" + message.substr(1, close - 1) + "': " + message.substr(close + 3);
}

// protobuf names a bad enum value's type ("… for type type.googleapis.com/armature.v1.Space"); the
// caller needs the names it would have taken.
std::string AllowedEnumValues(const std::string& message, const google::protobuf::DescriptorPool& pool) {
  static constexpr std::string_view kTypePrefix = "for type type.googleapis.com/";
  const size_t at = message.rfind(kTypePrefix);
  if (at == std::string::npos) return "";
  const google::protobuf::EnumDescriptor* type = pool.FindEnumTypeByName(message.substr(at + kTypePrefix.size()));
  if (type == nullptr) return "";
  std::string allowed;
  for (int i = 0; i < type->value_count(); ++i) allowed += (i ? ", " : "") + type->value(i)->name();
  return "; allowed: " + allowed + " (any case)";
}

}  // namespace

grpc::Status CheckJsonSyntax(std::string_view json, const std::string& where) {
  try {
    [[maybe_unused]] const auto parsed = nlohmann::json::parse(json);
  } catch (const nlohmann::json::parse_error& e) {
    std::string what = e.what();
    if (const size_t bracket = what.find("] "); what.rfind("[json.exception", 0) == 0 && bracket != std::string::npos)
      what = what.substr(bracket + 2);
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                        where + ": malformed JSON (byte " + std::to_string(e.byte) + "): " + what);
  } catch (const nlohmann::json::exception& e) {
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT, where + ": " + e.what());
  }
  return grpc::Status::OK;
}

grpc::Status JsonToMessage(std::string_view json, google::protobuf::Message* message, const std::string& where,
                           const std::string& field_label) {
  // protobuf's parser shows an excerpt but no position; nlohmann's gives the
  // line and column, so it checks the syntax first.
  if (auto st = CheckJsonSyntax(json, where); !st.ok()) return st;
  google::protobuf::util::JsonParseOptions options;
  options.ignore_unknown_fields = false;
  // "world" as well as "WORLD": the CLI prints enum values in lower case.
  options.case_insensitive_enum_parsing = true;
  const auto status = google::protobuf::util::JsonStringToMessage(
      google::protobuf::StringPiece(json.data(), json.size()), message, options);
  if (!status.ok()) {
    const std::string what(status.message());
    const auto* pool = message->GetDescriptor()->file()->pool();
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                        NameTheField(what, where, field_label) + AllowedEnumValues(what, *pool));
  }
  return grpc::Status::OK;
}

bool MessageToJson(const google::protobuf::Message& message, size_t max_bytes, std::string* out) {
  // Room for the usual answer up front (floats take about 3 times their 4
  // bytes), so the buffer seldom grows by copying.
  out->reserve(std::min(max_bytes, 3 * message.ByteSizeLong() + 64));
  return AppendMessageJson(message, max_bytes, out);
}

std::string MessageToJson(const google::protobuf::Message& message) {
  std::string out;
  (void)MessageToJson(message, std::numeric_limits<size_t>::max(), &out);
  return out;
}

}  // namespace armature::server::gateway
