// Wavefront OBJ rest meshes: positions, normals and faces.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "armature/engine/io/import_limits.h"
#include "armature/engine/mesh/mesh.h"
#include "armature/base/status.h"

namespace armature {

// Parses `v`, `vn`, `vt` and `f` statements (face corners as v, v/t, v//n or
// v/t/n, 1-based or negative = relative to the end); polygons are
// triangulated as fans. Vertex indices are the file's `v` order. A vertex's
// normal is the (averaged) `vn` its corners name, or computed from the faces
// when the file has none. Other statements (o, g, s, usemtl, mtllib, l, p)
// are ignored. The mesh is unbound (no joints) and finalized. Errors are
// INVALID_ARGUMENT naming the line, e.g. "line 12: vertex index 40 is out of
// range (30 vertices so far)". Repairs are appended to `warnings`. More
// vertices than limits.max_mesh_vertices is RESOURCE_EXHAUSTED.
StatusOr<Mesh> ParseObj(std::string_view text, std::string_view name, std::vector<std::string>* warnings = nullptr,
                        const ImportLimits& limits = {});

}  // namespace armature
