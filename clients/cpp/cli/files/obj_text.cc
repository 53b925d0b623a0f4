#include "obj_text.h"

#include <charconv>

namespace armature::cli {
namespace {

// Shortest text that reads back as the same float.
void AppendFloat(std::string& out, float v) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);
  out.append(buf, end);
}

void AppendTriple(std::string& out, std::string_view tag, std::span<const float> values, size_t vertex) {
  out.append(tag);
  for (size_t k = 0; k < 3; ++k) {
    out += ' ';
    AppendFloat(out, values[3 * vertex + k]);
  }
  out += '\n';
}

}  // namespace

std::string ObjText(std::span<const float> positions, std::span<const float> normals,
                    std::span<const uint32_t> triangles, std::string_view comment) {
  std::string out;
  out.append("# ").append(comment).append("\n");
  const size_t vertices = positions.size() / 3;
  const bool with_normals = normals.size() == positions.size();
  for (size_t v = 0; v < vertices; ++v) AppendTriple(out, "v", positions, v);
  if (with_normals)
    for (size_t v = 0; v < vertices; ++v) AppendTriple(out, "vn", normals, v);
  for (size_t t = 0; t + 2 < triangles.size(); t += 3) {
    out += 'f';
    for (size_t k = 0; k < 3; ++k) {
      const std::string index = std::to_string(triangles[t + k] + 1);  // OBJ counts from 1
      out.append(" ").append(index);
      if (with_normals) out.append("//").append(index);
    }
    out += '\n';
  }
  return out;
}

}  // namespace armature::cli
