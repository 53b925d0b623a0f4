#include "cli_context.h"

#include <iostream>

#include <google/protobuf/util/json_util.h>

namespace armature::cli {

client::Client CliContext::MakeClient() const {
  client::ClientOptions o = client::ClientOptions::FromEnvironment();
  if (!server.empty()) o.target = server;
  if (!token.empty()) o.token = token;
  if (!ca_file.empty()) o.ca_file = ca_file;
  o.timeout = std::chrono::milliseconds(static_cast<int64_t>(timeout_seconds * 1000));
  return client::Client(o);
}

std::string CliContext::Target() const {
  return server.empty() ? client::ClientOptions::FromEnvironment().target : server;
}

nlohmann::json ToJson(const google::protobuf::Message& message) {
  std::string out;
  google::protobuf::util::JsonPrintOptions options;
  options.always_print_primitive_fields = true;
  options.always_print_enums_as_ints = false;
  (void)google::protobuf::util::MessageToJsonString(message, &out, options);
  return nlohmann::json::parse(out);
}

void PrintJson(const nlohmann::json& j, bool pretty) { std::cout << j.dump(pretty ? 2 : -1) << "\n"; }

}  // namespace armature::cli
