// deform: one Laplacian / ARAP edit of an imported mesh.
#include <cmath>
#include <cstdio>
#include <map>
#include <stdexcept>

#include "cli_context.h"
#include "cli_messages.h"

namespace armature::cli {
namespace {

struct DeformFlags {
  std::string mesh;
  std::string weights = "uniform";
  std::string method = "laplacian";
  std::vector<uint32_t> fixed;
  std::vector<std::string> handles;  // IDX=x,y,z
};

// "12=0.5,1,-2" → a handle; anything else names the flag and the value.
v1::DeformHandle ParseHandle(const std::string& text) {
  const auto bad = [&](const std::string& why) {
    return std::invalid_argument("--handle " + text + ": " + why + " (expected IDX=x,y,z)");
  };
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0) throw bad("no '='");
  v1::DeformHandle h;
  size_t used = 0;
  const std::string index = text.substr(0, eq);
  unsigned long v = 0;
  try {
    v = std::stoul(index, &used);
  } catch (const std::exception&) {
    throw bad("the index is not a number");
  }
  if (used != index.size() || index[0] == '-' || v > 0xffffffffUL) throw bad("the index is not a vertex index");
  h.set_index(static_cast<uint32_t>(v));
  std::string rest = text.substr(eq + 1);
  for (int a = 0; a < 3; ++a) {
    const auto comma = rest.find(',');
    const std::string part = a < 2 ? rest.substr(0, comma) : rest;
    if ((a < 2 && comma == std::string::npos) || part.empty()) throw bad("needs three coordinates");
    double x = 0;
    try {
      x = std::stod(part, &used);
    } catch (const std::exception&) {
      throw bad("'" + part + "' is not a number");
    }
    if (used != part.size() || !std::isfinite(x)) throw bad("'" + part + "' is not a finite number");
    h.add_position(x);
    if (a < 2) rest = rest.substr(comma + 1);
  }
  return h;
}

}  // namespace

void AddDeformCommand(CLI::App& app, CliContext& ctx) {
  auto* cmd = app.add_subcommand("deform", "Deform a mesh: move handle vertices, hold fixed ones (Laplacian or ARAP)");
  auto f = std::make_shared<DeformFlags>();
  cmd->add_option("MESH", f->mesh, "Mesh name")->required();
  cmd->add_option("--weights", f->weights, "uniform or cotan")
      ->capture_default_str()
      ->transform(OneOf({"uniform", "cotan"}));
  cmd->add_option("--method", f->method, "laplacian or arap")
      ->capture_default_str()
      ->transform(OneOf({"laplacian", "arap"}));
  cmd->add_option("--fixed", f->fixed, "Vertices held at rest: i,j,k,…")->delimiter(',');
  cmd->add_option("--handle", f->handles, "A moved vertex: IDX=x,y,z (repeatable)")->required();
  cmd->callback([&ctx, f] {
    ctx.run = [&ctx, f] {
      v1::DeformRequest request;
      request.set_mesh(f->mesh);
      request.set_weights(f->weights == "cotan" ? v1::COTANGENT : v1::UNIFORM);
      request.set_method(f->method == "arap" ? v1::ARAP : v1::LAPLACIAN);
      for (uint32_t v : f->fixed) request.add_fixed(v);
      for (const auto& h : f->handles) *request.add_handles() = ParseHandle(h);
      client::Client client = ctx.MakeClient();
      const auto response = client.Deform(request);
      if (ctx.json) {
        PrintJson({{"mesh", response.mesh()},
                   {"positions", std::vector<float>(response.positions().begin(), response.positions().end())}},
                  false);
      } else {
        std::printf("mesh %s: %d vertices (%s, %s weights)\n", response.mesh().c_str(), response.positions_size() / 3,
                    f->method.c_str(), f->weights.c_str());
        for (int v = 0; v + 2 < response.positions_size(); v += 3)
          std::printf("%d %.9g %.9g %.9g\n", v / 3, response.positions(v), response.positions(v + 1),
                      response.positions(v + 2));
      }
      return 0;
    };
  });
}

}  // namespace armature::cli
