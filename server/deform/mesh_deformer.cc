#include "server/deform/mesh_deformer.h"

#include <algorithm>
#include <string>

#include "armature/engine/mesh/mesh.h"
#include "server/deform/deform_validation.h"
#include "server/rpc/request_validation.h"

namespace armature::server {

StatusOr<MeshDeformer> MeshDeformer::Create(const Catalog& catalog, const Limits& limits, const v1::DeformSetup& setup,
                                            std::vector<uint32_t> handles) {
  auto ref = catalog.FindMesh(setup.mesh());
  if (!ref.ok()) return ref.status();
  const Mesh& mesh = *ref->part->mesh;
  if (static_cast<int64_t>(mesh.vertex_count()) > limits.max_mesh_vertices)
    return Status::ResourceExhausted("mesh '" + setup.mesh() + "' has " + std::to_string(mesh.vertex_count()) +
                                     " vertices, over max_mesh_vertices (" + std::to_string(limits.max_mesh_vertices) +
                                     ")");
  ARMATURE_RETURN_IF_ERROR(ValidateDeformSetup(setup));

  LaplacianModelOptions model_options;
  model_options.weights = setup.weights() == v1::COTANGENT ? LaplacianWeights::kCotangent : LaplacianWeights::kUniform;
  model_options.max_vertices = static_cast<size_t>(limits.max_mesh_vertices);
  const std::span<const float> positions(mesh.positions.empty() ? nullptr : mesh.positions.front().data(),
                                         3 * mesh.vertex_count());
  auto model = BuildLaplacianModel(positions, mesh.triangles, model_options);
  if (!model.ok()) return model.status();

  DeformationConstraints c;
  c.handles = std::move(handles);
  c.fixed.assign(setup.fixed().begin(), setup.fixed().end());
  c.region_of_interest.assign(setup.region_of_interest().begin(), setup.region_of_interest().end());
  c.mode = setup.soft() ? ConstraintMode::kSoft : ConstraintMode::kHard;
  if (setup.soft() && setup.soft_weight() != 0) c.soft_weight = setup.soft_weight();

  MeshDeformer d;
  d.mesh_ = std::move(*ref);
  d.handles_ = c.handles;
  if (setup.method() == v1::ARAP) {
    auto solver = ArapSolver::Create(*model, c);
    if (!solver.ok()) return solver.status();
    d.arap_.emplace(std::move(*solver));
    if (setup.arap_iterations() > 0) d.arap_options_.max_iterations = setup.arap_iterations();
  } else {
    auto solver = DeformationSolver::Create(*model, c);
    if (!solver.ok()) return solver.status();
    d.laplacian_.emplace(std::move(*solver));
  }
  return d;
}

size_t MeshDeformer::vertex_count() const { return mesh_.part->mesh->vertex_count(); }

std::vector<double> MeshDeformer::RestHandlePositions() const {
  std::vector<double> rest;
  rest.reserve(3 * handles_.size());
  for (uint32_t h : handles_)
    for (int a = 0; a < 3; ++a) rest.push_back(mesh_.part->mesh->positions[h][a]);
  return rest;
}

Status MeshDeformer::Solve(std::span<const double> handle_positions, const std::string& field,
                           v1::DeformResponse* response) {
  if (arap_) positions_.resize(3 * vertex_count());  // Laplacian answers straight into the response
  ARMATURE_RETURN_IF_ERROR(SolveInto(handle_positions, field, arap_options_.warm_start, positions_, response));
  arap_options_.warm_start = true;
  return Status::Ok();
}

Status MeshDeformer::SolveFresh(std::span<const double> handle_positions, const std::string& field,
                                v1::DeformResponse* response) const {
  std::vector<double> positions(arap_ ? 3 * vertex_count() : 0);  // Laplacian answers straight into the response
  return SolveInto(handle_positions, field, false, positions, response);
}

Status MeshDeformer::SolveInto(std::span<const double> handle_positions, const std::string& field, bool warm_start,
                               std::span<double> positions, v1::DeformResponse* response) const {
  ARMATURE_RETURN_IF_ERROR(ValidateHandlePositions(handle_positions, handles_.size(), field));
  // The answer is written straight into the response's buffer (no zero
  // fill, no double copy for Laplacian): a drag's answer is 3 floats per
  // vertex, the bulk of a move's time on a large mesh besides the solve.
  auto* out = response->mutable_positions();
  out->Clear();
  const size_t n = 3 * vertex_count();
  out->Reserve(static_cast<int>(n));
  const std::span<float> floats(out->AddNAlreadyReserved(static_cast<int>(n)), n);
  int iterations = 0;
  Status solved = Status::Ok();
  if (arap_) {
    ArapOptions options = arap_options_;
    options.warm_start = warm_start;
    auto report = arap_->Solve(handle_positions, options, positions);  // doubles: a session's warm start
    if (report.ok()) {
      iterations = report->iterations;
      std::transform(positions.begin(), positions.end(), floats.begin(),
                     [](double x) { return static_cast<float>(x); });
    }
    solved = report.status();
  } else {
    solved = laplacian_->Solve(handle_positions, floats);
  }
  if (!solved.ok()) {
    out->Clear();
    return solved;
  }
  response->set_mesh(mesh_.part->name);
  response->set_iterations(iterations);
  return Status::Ok();
}

size_t MeshDeformer::memory_bytes() const {
  const size_t solver = arap_ ? arap_->memory_bytes() + arap_->model().memory_bytes()
                              : laplacian_->memory_bytes() + laplacian_->model().memory_bytes();
  return sizeof(*this) + solver + handles_.capacity() * sizeof(uint32_t) + positions_.capacity() * sizeof(double);
}

}  // namespace armature::server
