// create-clip: a clip from a keys file (the CreateClipRequest as proto3 JSON).
#include <memory>
#include <string>
#include <vector>

#include "cli_context.h"
#include "files/motion_file.h"

namespace armature::cli {
namespace {

// FILE.json as a CreateClipRequest; throws naming the file and the problem.
v1::CreateClipRequest ReadKeysFile(const std::string& path) {
  v1::CreateClipRequest request;
  ReadJsonMessageFile(path, "--keys",
                      "keys (proto3 JSON of armature.v1.CreateClipRequest, e.g. "
                      "{\"tracks\":[{\"joint\":\"Head\",\"times\":[0,0.5],\"rotations\":[1,0,0,0,1,0,0,0]}]})",
                      request);
  return request;
}

}  // namespace

void AddCreateClipCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("create-clip",
                                 "Create a clip from keys per joint (FILE.json: the CreateClipRequest as proto3 JSON); "
                                 "prints it as import does");
  auto skeleton = std::make_shared<std::string>();
  auto keys = std::make_shared<std::string>();
  auto name = std::make_shared<std::string>();
  auto replace = std::make_shared<bool>(false);
  auto merge = std::make_shared<bool>(false);
  cmd->add_option("--skeleton", *skeleton, "The skeleton the clip animates (overrides the file's)");
  cmd->add_option("--keys", *keys,
                  "The keys file: {\"tracks\":[{\"joint\":…,\"times\":[…],\"rotations\":[w,x,y,z,…],"
                  "\"translations\":[x,y,z,…],\"interpolation\":\"LINEAR\"}]}")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--name", *name,
                  "The new asset's name (overrides the file's); the clip is NAME, a clip of the skeleton");
  cmd->add_flag("--replace", *replace, "Replace an existing asset of the same name");
  cmd->add_flag("--merge", *merge,
                "Edit the clip stored under NAME: the file's tracks replace those joints' tracks, "
                "a track without times deletes one, the others are kept");
  cmd->callback([&ctx, skeleton, keys, name, replace, merge] {
    ctx.run = [&ctx, skeleton, keys, name, replace, merge] {
      v1::CreateClipRequest request = ReadKeysFile(*keys);
      if (!skeleton->empty()) request.set_skeleton(*skeleton);
      if (!name->empty()) request.set_name(*name);
      if (*replace) request.set_replace(true);
      if (*merge) request.set_merge(true);
      const auto response = ctx.MakeClient().CreateClip(request);
      auto summary = ImportSummary(response.asset());
      summary["clip"] = ToJson(response.clip());
      summary["warnings"] = std::vector<std::string>(response.warnings().begin(), response.warnings().end());
      PrintJson(summary);
      return 0;
    };
  });
}

}  // namespace armature::cli
