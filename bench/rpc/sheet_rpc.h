// The 100k-vertex sheet (sheet_mesh.h) imported once, as OBJ bytes made
// here, into the shared bench server: the deformation RPC benchmarks (sessions
// and the unary cache) all edit this one mesh. Also an answer of its size.
#pragma once

#include <string>

#include "armature/v1/deform.pb.h"
#include "rpc_bench_server.h"
#include "sheet_mesh.h"

namespace armature_bench {

inline constexpr char kSheetName[] = "sheet";

inline const std::string& ImportedSheet() {
  static const std::string name = [] {
    Server().client->Import({"sheet.obj", armature::fixtures::ToObj(Sheet())}, kSheetName);
    return std::string(kSheetName);
  }();
  return name;
}

// An answer on the sheet (its rest positions: 3 × 100,489 floats), the
// payload a move or a cache hit carries; made without the server.
inline armature::v1::DeformResponse SheetAnswer() {
  armature::v1::DeformResponse r;
  r.set_mesh(kSheetName);
  const auto& p = Sheet().positions;
  r.mutable_positions()->Reserve(static_cast<int>(p.size()));
  for (Eigen::Index v = 0; v < p.rows(); ++v)
    for (int k = 0; k < 3; ++k) r.add_positions(static_cast<float>(p(v, k)));
  return r;
}

}  // namespace armature_bench
