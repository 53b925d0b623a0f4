// export: a clip written to a file in the format its name asks for.
#include <iostream>
#include <stdexcept>

#include "cli_context.h"
#include "cli_messages.h"
#include "files/output_file.h"

namespace armature::cli {
namespace {

// The format to write `out` in: --format when given, else the extension.
std::string ExportFormat(const std::string& out, const std::string& format_flag, bool with_meshes) {
  const std::string format = format_flag.empty() ? ExtensionFormat(out) : format_flag;
  if (format != "bvh" && format != "glb" && format != "gltf")
    throw std::runtime_error("cannot tell the export format from the file name " + out +
                             ": name a .glb, .gltf or .bvh file or pass --format glb|gltf|bvh");
  if (with_meshes && format == "bvh")
    throw std::runtime_error("--with-meshes needs glTF: BVH holds no meshes; use -o " + WithExtension(out, ".glb"));
  return format;
}

}  // namespace

void AddExportCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd =
      app.add_subcommand("export", "Export a clip to a file, in the format of its extension (.glb, .gltf, .bvh)");
  auto clip = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto format = std::make_shared<std::string>();
  auto with_meshes = std::make_shared<bool>(false);
  cmd->add_option("CLIP", *clip, "Clip name")->required();
  cmd->add_option("-o,--output", *out, "Output file; its extension says the format (.glb, .gltf, .bvh)")->required();
  cmd->add_option("--format", *format, "Write this format whatever the extension: glb, gltf or bvh")
      ->transform(OneOf({"bvh", "glb", "gltf"}));
  cmd->add_flag("--with-meshes", *with_meshes,
                "glTF: also write the character's meshes (skinned to the clip's skeleton) and morph targets");
  cmd->callback([&ctx, clip, out, format, with_meshes] {
    ctx.run = [&ctx, clip, out, format, with_meshes] {
      // Before any call: a refusal writes nothing.
      const std::string written = ExportFormat(*out, *format, *with_meshes);
      const auto response = ctx.MakeClient().ExportClip(*clip, written, *with_meshes);
      WriteOutputFile(*out, response.data());
      if (ctx.json)
        PrintJson({{"clip", *clip}, {"file", *out}, {"format", written}, {"bytes", response.data().size()}}, false);
      else
        std::cerr << "wrote " << *out << " (" << written << ", " << response.data().size() << " bytes)\n";
      return 0;
    };
  });
}

}  // namespace armature::cli
