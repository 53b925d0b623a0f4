// A triangle mesh as Wavefront OBJ text (`armature skin -o posed.obj`), which
// any 3D tool opens and `armature import` reads back.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

namespace armature::cli {

// `positions` and `normals` are x, y, z per vertex (`normals` may be empty),
// `triangles` three 0-based vertex indices each; `comment` becomes a leading
// "# …" line.
std::string ObjText(std::span<const float> positions, std::span<const float> normals,
                    std::span<const uint32_t> triangles, std::string_view comment);

}  // namespace armature::cli
