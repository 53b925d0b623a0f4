// One mesh edit's solver, resolved from an API setup: the mesh, its Laplacian
// model and a factored DeformationSolver or ArapSolver. A unary Deform takes
// one from the DeformerCache (shared, solved with the const SolveFresh); a
// DeformSession keeps its own for its whole life (the factorization is the
// session's memory, freed with it).
#pragma once

#include <memory>
#include <optional>
#include <span>
#include <vector>

#include "armature/engine/deform/arap.h"
#include "armature/engine/deform/laplacian_editor.h"
#include "armature/base/status.h"
#include "armature/v1/deform.pb.h"
#include "server/assets/asset_store.h"
#include "server/rpc/limits.h"

namespace armature::server {

class MeshDeformer {
 public:
  // NOT_FOUND for an unknown mesh, RESOURCE_EXHAUSTED naming
  // max_mesh_vertices for a mesh over it, INVALID_ARGUMENT (from the engine)
  // for bad constraints: out-of-range or fixed handles, a connected
  // component without any constraint.
  static StatusOr<MeshDeformer> Create(const Catalog& catalog, const Limits& limits, const v1::DeformSetup& setup,
                                       std::vector<uint32_t> handles);

  // `handle_positions`: x,y,z per handle (finite; checked, naming `field`).
  // Fills response positions (and iterations for ARAP). ARAP warm-starts
  // from the previous result after the first call (a session's drag).
  Status Solve(std::span<const double> handle_positions, const std::string& field, v1::DeformResponse* response);
  // The answer a newly made deformer gives: ARAP starts from the rest shape,
  // never from an earlier call's result, so the answer depends on the request
  // alone. Const and thread-safe: one cached deformer serves concurrent calls.
  Status SolveFresh(std::span<const double> handle_positions, const std::string& field,
                    v1::DeformResponse* response) const;

  // x,y,z per handle at its rest position (a session's first answer: the rest shape).
  std::vector<double> RestHandlePositions() const;
  size_t vertex_count() const;
  const PartRef<NamedMesh>& mesh() const { return mesh_; }
  // What this deformer holds: the factorization (L's nonzeros, counted by the
  // engine after the symbolic analysis), the handle basis, the Laplacian
  // model and the warm-start positions. The mesh itself is the store's.
  size_t memory_bytes() const;

 private:
  MeshDeformer() = default;
  Status SolveInto(std::span<const double> handle_positions, const std::string& field, bool warm_start,
                   std::span<double> positions, v1::DeformResponse* response) const;

  PartRef<NamedMesh> mesh_;
  std::vector<uint32_t> handles_;
  std::optional<DeformationSolver> laplacian_;
  std::optional<ArapSolver> arap_;
  ArapOptions arap_options_;
  std::vector<double> positions_;  // the last result (ARAP's warm start); sized by the first Solve
};

}  // namespace armature::server
