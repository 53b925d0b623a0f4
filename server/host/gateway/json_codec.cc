#include "server/host/gateway/json_codec.h"

#include <google/protobuf/util/json_util.h>
#include <nlohmann/json.hpp>

namespace armature::server::gateway {
namespace {

// protobuf says "(times[1]): invalid value …"; we say "<label> 'times[1]': invalid value …".
std::string NameTheField(const std::string& message, const std::string& where, const std::string& label) {
  const size_t close = message.find("): ");
  if (message.empty() || message[0] != '(' || close == std::string::npos) return where + ": " + message;
  return label + " '" + message.substr(1, close - 1) + "': " + message.substr(close + 3);
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
  options.case_insensitive_enum_parsing = false;
  const auto status = google::protobuf::util::JsonStringToMessage(
      google::protobuf::StringPiece(json.data(), json.size()), message, options);
  if (!status.ok())
    return grpc::Status(grpc::StatusCode::INVALID_ARGUMENT,
                        NameTheField(std::string(status.message()), where, field_label));
  return grpc::Status::OK;
}

std::string MessageToJson(const google::protobuf::Message& message) {
  google::protobuf::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  options.preserve_proto_field_names = false;
  std::string out;
  // Printing a valid message cannot fail for the types the API uses.
  (void)google::protobuf::util::MessageToJsonString(message, &out, options);
  return out;
}

}  // namespace armature::server::gateway
