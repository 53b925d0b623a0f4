// The 100k-vertex sheet (sheet_mesh.h) imported once, as OBJ bytes made
// here, into the shared bench server: the deformation RPC benchmarks (sessions
// and the unary cache) all edit this one mesh.
#pragma once

#include <string>

#include "rpc_bench_server.h"
#include "sheet_mesh.h"

namespace armature_bench {

inline const std::string& ImportedSheet() {
  static const std::string name = [] {
    Server().client->Import({"sheet.obj", armature::fixtures::ToObj(Sheet())}, "sheet");
    return std::string("sheet");
  }();
  return name;
}

}  // namespace armature_bench
