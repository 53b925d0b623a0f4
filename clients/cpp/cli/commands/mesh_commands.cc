// skin: a mesh posed by a clip at a time, as world-space positions and normals
// (printed, or written as an OBJ file with -o).
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <limits>
#include <map>
#include <sstream>
#include <span>
#include <stdexcept>

#include "cli_context.h"
#include "cli_messages.h"
#include "files/motion_file.h"
#include "files/obj_text.h"
#include "files/output_file.h"

namespace armature::cli {
namespace {

const std::map<std::string, v1::SkinningMethod> kMethods = {{"lbs", v1::LBS}, {"dqs", v1::DQS}};

struct SkinFlags {
  std::string mesh, clip, motion, method = "lbs", out;
  double time = 0;
  bool loop = false;
  std::vector<float> weights;
};

std::vector<float> Floats(const google::protobuf::RepeatedField<float>& values) {
  return {values.begin(), values.end()};
}

// 0.5, not 0.500000.
std::string TimeText(double seconds) {
  std::ostringstream out;
  out << seconds;
  return out.str();
}

template <class T>
std::span<const T> Span(const google::protobuf::RepeatedField<T>& values) {
  return {values.data(), static_cast<size_t>(values.size())};
}

}  // namespace

void AddSkinCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd =
      app.add_subcommand("skin", "Skin a mesh by a clip or a motion at a time (world-space positions and normals)");
  auto f = std::make_shared<SkinFlags>();
  cmd->add_option("MESH", f->mesh, "Mesh name")->required();
  auto* clip = cmd->add_option("--clip", f->clip, "Clip posing the mesh (its joints and morph weights)");
  cmd->add_option("--motion", f->motion, "A motion (clips in layers) as proto3 JSON posing the mesh, instead of --clip")
      ->excludes(clip)
      ->check(CLI::ExistingFile);
  cmd->add_option("--time,-t", f->time, "Clip (or motion) time in seconds")->required();
  cmd->add_option("--method", f->method, "lbs or dqs")->capture_default_str()->transform(OneOf({"lbs", "dqs"}));
  cmd->add_flag("--loop", f->loop, "Wrap times past the end (default: clamp)");
  cmd->add_option("--weights", f->weights, "Morph weights overriding the clip's, one per target")->delimiter(',');
  cmd->add_option("-o,--output", f->out, "Also write the skinned mesh to this .obj file");
  cmd->callback([&ctx, cmd, f] {
    if (cmd->count("--clip") + cmd->count("--motion") == 0) throw CLI::RequiredError("--clip or --motion");
    ctx.run = [&ctx, f] {
      if (!f->out.empty() && ExtensionFormat(f->out) != "obj")
        throw std::runtime_error("cannot tell the format from the file name " + f->out +
                                 ": skin -o writes OBJ, name a .obj file");
      client::Client client = ctx.MakeClient();
      v1::SkinMeshRequest request;
      request.set_mesh(f->mesh);
      if (f->motion.empty())
        request.set_clip(f->clip);
      else
        *request.mutable_motion() = ReadMotionFile(f->motion);
      request.set_time(f->time);
      request.set_wrap(f->loop ? v1::LOOP : v1::CLAMP);
      request.set_method(kMethods.at(f->method));
      for (float w : f->weights) request.add_morph_weights(w);
      const auto response = client.SkinMesh(request);
      if (!f->out.empty()) {
        const v1::MeshGeometry geometry = client.GetMeshGeometry(f->mesh);  // the triangles
        const std::string obj =
            ObjText(Span(response.positions()), Span(response.normals()), Span(geometry.triangles()),
                    "armature skin " + f->mesh + (f->motion.empty() ? " --clip " + f->clip : " --motion " + f->motion) +
                        " --time " + TimeText(f->time) + " --method " + f->method);
        WriteOutputFile(f->out, obj);
        std::cerr << "wrote " << f->out << " (" << response.vertex_count() << " vertices, "
                  << geometry.triangles_size() / 3 << " triangles)\n";
      }
      if (ctx.json) {
        // Ordered: the mesh and count first, then the (long) arrays.
        const nlohmann::ordered_json j = {{"mesh", response.mesh()},
                                          {"vertexCount", response.vertex_count()},
                                          {"positions", Floats(response.positions())},
                                          {"normals", Floats(response.normals())}};
        std::cout << j.dump() << "\n";
        return 0;
      }
      float lo[3], hi[3];
      std::fill_n(lo, 3, std::numeric_limits<float>::infinity());
      std::fill_n(hi, 3, -std::numeric_limits<float>::infinity());
      for (int i = 0; i < response.positions_size(); ++i) {
        lo[i % 3] = std::min(lo[i % 3], response.positions(i));
        hi[i % 3] = std::max(hi[i % 3], response.positions(i));
      }
      std::printf("mesh %s: %d vertices skinned (%s) by %s at %.6f s\n", response.mesh().c_str(),
                  response.vertex_count(), f->method.c_str(), (f->motion.empty() ? f->clip : f->motion).c_str(),
                  f->time);
      if (response.vertex_count() > 0)
        std::printf("bounds min (%.6g, %.6g, %.6g) max (%.6g, %.6g, %.6g)\n", lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]);
      return 0;
    };
  });
}

}  // namespace armature::cli
