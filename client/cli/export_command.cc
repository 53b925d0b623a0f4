// export: a clip written to a file in the format its name asks for.
#include <iostream>
#include <stdexcept>

#include "cli_context.h"
#include "output_file.h"

namespace armature::cli {
namespace {

// The format to write `out` in: --format when given, else the extension.
// Only BVH is written today; glTF is refused (not written in the wrong format).
std::string ExportFormat(const std::string& out, const std::string& format_flag) {
  const std::string format = format_flag.empty() ? ExtensionFormat(out) : format_flag;
  if (format == "bvh") return format;
  if (format == "glb" || format == "gltf")
    throw std::runtime_error("cannot export to " + out + ": glTF export (" + format +
                             ") is not available yet, only BVH; use -o " + WithExtension(out, ".bvh") +
                             " (or --format bvh)");
  throw std::runtime_error("cannot tell the export format from the file name " + out +
                           ": name a .bvh file or pass --format bvh (formats: bvh; glb and gltf not yet)");
}

}  // namespace

void AddExportCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("export", "Export a clip to a file, in the format of its extension (.bvh)");
  auto clip = std::make_shared<std::string>();
  auto out = std::make_shared<std::string>();
  auto format = std::make_shared<std::string>();
  cmd->add_option("CLIP", *clip, "Clip name")->required();
  cmd->add_option("-o,--output", *out, "Output file; its extension says the format (.bvh)")->required();
  cmd->add_option("--format", *format, "Write this format whatever the extension: bvh (glb and gltf: not yet)")
      ->check(CLI::IsMember({"bvh", "glb", "gltf"}));
  cmd->callback([&ctx, clip, out, format] {
    ctx.run = [&ctx, clip, out, format] {
      const std::string written = ExportFormat(*out, *format);  // before any call: a refusal writes nothing
      const auto response = ctx.MakeClient().ExportClip(*clip);
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
