// What every `armature` subcommand shares: connection flags and output helpers.
#pragma once

#include <functional>
#include <string>

#include <CLI/CLI.hpp>
#include <google/protobuf/message.h>
#include <nlohmann/json.hpp>

#include "armature/client.h"

namespace armature::cli {

struct CliContext {
  std::string server;
  std::string token;
  std::string ca_file;
  double timeout_seconds = 30;
  bool json = false;         // --json: print JSON instead of text
  std::function<int()> run;  // set by the chosen subcommand

  client::Client MakeClient() const;
  // The server's address: --server, else $ARMATURE_SERVER, else localhost:50051.
  std::string Target() const;
};

// proto3 JSON of a message (lowerCamelCase, defaults printed), as a json value.
nlohmann::json ToJson(const google::protobuf::Message& message);
// Prints JSON on stdout, indented when `pretty`.
void PrintJson(const nlohmann::json& j, bool pretty = true);

// What `import` prints of a new asset: {"asset":…,"skeletons":[…],"clips":[…],"meshes":[…]}.
nlohmann::json ImportSummary(const v1::AssetInfo& asset);

// Each subcommand registers itself on the app.
void AddImportCommand(CLI::App& app, CliContext& ctx);
void AddListCommand(CLI::App& app, CliContext& ctx);
void AddInfoCommand(CLI::App& app, CliContext& ctx);
void AddPoseCommand(CLI::App& app, CliContext& ctx);
void AddStreamCommand(CLI::App& app, CliContext& ctx);
void AddPlayCommand(CLI::App& app, CliContext& ctx);
void AddCrowdCommand(CLI::App& app, CliContext& ctx);
void AddExportCommand(CLI::App& app, CliContext& ctx);
void AddDeleteCommand(CLI::App& app, CliContext& ctx);
void AddHealthCommand(CLI::App& app, CliContext& ctx);
void AddDeformCommand(CLI::App& app, CliContext& ctx);
void AddIkCommand(CLI::App& app, CliContext& ctx);
void AddSkinCommand(CLI::App& app, CliContext& ctx);
void AddCreateClipCommand(CLI::App& app, CliContext& ctx);
void AddRetargetCommand(CLI::App& app, CliContext& ctx);

}  // namespace armature::cli
