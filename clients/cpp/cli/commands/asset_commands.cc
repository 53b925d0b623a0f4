// import, list, info, delete, health.
#include <iomanip>
#include <iostream>
#include <sstream>
#include <string>

#include "cli_context.h"
#include "cli_messages.h"

namespace armature::cli {

nlohmann::json ImportSummary(const v1::AssetInfo& a) {
  nlohmann::json j = {{"asset", a.name()},
                      {"skeletons", nlohmann::json::array()},
                      {"clips", nlohmann::json::array()},
                      {"meshes", nlohmann::json::array()}};
  for (const auto& s : a.skeletons()) j["skeletons"].push_back({{"name", s.name()}, {"joints", s.joint_count()}});
  for (const auto& c : a.clips())
    j["clips"].push_back({{"name", c.name()},
                          {"skeleton", c.skeleton()},
                          {"duration", c.duration()},
                          {"frames", c.frames()},
                          {"frameTime", c.frame_time()},
                          {"runtimeBytes", c.runtime_bytes()},
                          {"bytesPerJointSample", c.bytes_per_joint_sample()},
                          {"exact", c.exact()},
                          {"errorBoundCm", c.error_bound_cm()},
                          {"worstErrorCm", c.worst_error_cm()}});
  for (const auto& m : a.meshes()) j["meshes"].push_back({{"name", m.name()}, {"vertexCount", m.vertex_count()}});
  return j;
}

// The clip's runtime form as `list` shows it: "2.23 B/joint-sample (68410 bytes), within 0.01 cm (worst
// 0.0098 cm)", or "exact, 59.5 B/joint-sample (…)".
std::string RuntimeFormText(const v1::ClipInfo& c) {
  std::ostringstream out;
  out << std::setprecision(3);
  if (c.exact()) out << "exact, ";
  out << c.bytes_per_joint_sample() << " B/joint-sample (" << c.runtime_bytes() << " bytes)";
  if (!c.exact()) out << ", within " << c.error_bound_cm() << " cm (worst " << c.worst_error_cm() << " cm)";
  return out.str();
}

void AddImportCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("import", "Import a BVH, glTF/GLB, OBJ or FBX file; prints what it created as JSON");
  auto file = std::make_shared<std::string>();
  auto name = std::make_shared<std::string>();
  auto replace = std::make_shared<bool>(false);
  auto outside = std::make_shared<bool>(false);
  auto format = std::make_shared<std::string>();
  auto precision = std::make_shared<std::string>();
  cmd->add_option("FILE", *file, "The file to import")->required()->check(CLI::ExistingFile);
  cmd->add_option("--name", *name, "Asset name (default: the file's stem)");
  cmd->add_option("--format", *format,
                  "bvh, gltf, glb, obj or fbx, whatever the file name says (default: from its "
                  "extension, else its content)")
      ->transform(OneOf({"bvh", "gltf", "glb", "obj", "fbx"}));
  cmd->add_flag("--replace", *replace, "Replace an existing asset of the same name");
  cmd->add_flag("--allow-outside-resources", *outside,
                "Also upload the files a .gltf's buffer uris name outside its folder (absolute paths, '..', file: "
                "uris); by default only files in its folder or subfolders are sent");
  cmd->add_option("--clip-error", *precision,
                  "How closely the server keeps the clips: a bound in centimetres on points 3 cm from each joint, "
                  "in (0, 10], or 'exact' (the stored keys bit for bit); default: the server's --clip-error");
  cmd->callback([&ctx, file, name, replace, outside, format, precision] {
    ctx.run = [&ctx, file, name, replace, outside, format, precision] {
      const auto response = ctx.MakeClient().ImportFile(*file, *name, *replace, *outside, *format, *precision);
      auto summary = ImportSummary(response.asset());
      summary["warnings"] = std::vector<std::string>(response.warnings().begin(), response.warnings().end());
      PrintJson(summary);
      return 0;
    };
  });
}

void AddListCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("list", "List assets with their skeletons, clips and meshes");
  cmd->callback([&ctx] {
    ctx.run = [&ctx] {
      const auto assets = ctx.MakeClient().ListAssets();
      if (ctx.json) {
        PrintJson(ToJson(assets));
        return 0;
      }
      if (assets.assets().empty()) std::cout << "no assets\n";
      for (const auto& a : assets.assets()) {
        std::cout << a.name() << " (" << a.format() << ", " << a.size_bytes() << " bytes, " << a.imported_at() << ")\n";
        for (const auto& s : a.skeletons())
          std::cout << "  skeleton " << s.name() << ": " << s.joint_count() << " joints\n";
        for (const auto& c : a.clips())
          std::cout << "  clip     " << c.name() << ": " << c.duration() << " s, " << c.frames() << " frames, skeleton "
                    << c.skeleton() << ", " << RuntimeFormText(c) << "\n";
        for (const auto& m : a.meshes())
          std::cout << "  mesh     " << m.name() << ": " << m.vertex_count() << " vertices\n";
      }
      return 0;
    };
  });
}

void AddInfoCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("info", "Details of a clip, or of a skeleton with --skeleton, as JSON");
  auto name = std::make_shared<std::string>();
  auto skeleton = std::make_shared<bool>(false);
  cmd->add_option("NAME", *name, "Clip (or skeleton) name")->required();
  cmd->add_flag("--skeleton", *skeleton, "NAME is a skeleton: print its joint hierarchy");
  cmd->callback([&ctx, name, skeleton] {
    ctx.run = [&ctx, name, skeleton] {
      client::Client client = ctx.MakeClient();
      PrintJson(*skeleton ? ToJson(client.GetSkeleton(*name)) : ToJson(client.GetClip(*name)));
      return 0;
    };
  });
}

void AddDeleteCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("delete", "Delete an asset (or the asset owning a clip, skeleton or mesh)");
  auto name = std::make_shared<std::string>();
  cmd->add_option("NAME", *name, "Asset, clip, skeleton or mesh name")->required();
  cmd->callback([&ctx, name] {
    ctx.run = [&ctx, name] {
      const auto deleted = ctx.MakeClient().DeleteAsset(*name);
      if (ctx.json)
        PrintJson(ToJson(deleted));
      else
        std::cout << "deleted asset " << deleted.name() << "\n";
      return 0;
    };
  });
}

void AddHealthCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("health", "Exit 0 when the server reports SERVING");
  cmd->callback([&ctx] {
    ctx.run = [&ctx] {
      const bool ok = ctx.MakeClient().Healthy();
      const char* status = ok ? "SERVING" : "NOT_SERVING";
      if (ctx.json)
        PrintJson({{"status", status}}, false);
      else
        std::cout << status << "\n";
      return ok ? 0 : 1;
    };
  });
}

}  // namespace armature::cli
