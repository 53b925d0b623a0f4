#include "armature/engine/io/obj/obj.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>

#include "armature/base/utf8.h"

namespace armature {

namespace {

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\v' || c == '\f'; }

// Splits a line into whitespace-separated tokens without allocating copies;
// `out` is reused across lines.
void Tokens(std::string_view line, std::vector<std::string_view>& out) {
  out.clear();
  size_t i = 0;
  while (i < line.size()) {
    while (i < line.size() && IsSpace(line[i])) ++i;
    const size_t start = i;
    while (i < line.size() && !IsSpace(line[i])) ++i;
    if (i > start) out.push_back(line.substr(start, i - start));
  }
}

std::string At(size_t line) { return "line " + std::to_string(line) + ": "; }

StatusOr<Eigen::Vector3f> ParseVector(const std::vector<std::string_view>& tokens, size_t line) {
  if (tokens.size() < 4)
    return Status::InvalidArgument(At(line) + "expected 3 numbers after '" + EscapeForMessage(tokens[0]) + "'");
  Eigen::Vector3d v;
  for (int c = 0; c < 3; ++c) {
    const std::string_view t = tokens[static_cast<size_t>(c) + 1];
    double x = 0;
    const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), x);
    if (ec != std::errc() || end != t.data() + t.size())
      return Status::InvalidArgument(At(line) + "'" + EscapeForMessage(t) + "' is not a number");
    if (!std::isfinite(x) || std::abs(x) > 3e38)
      return Status::InvalidArgument(At(line) + "'" + EscapeForMessage(t) + "' is not a finite float");
    v[c] = x;
  }
  return Eigen::Vector3f(v.cast<float>());
}

// A face index: 1-based, or negative counting back from the latest element.
StatusOr<uint32_t> ResolveIndex(std::string_view t, size_t defined, const char* what, const char* plural,
                                size_t line) {
  long long i = 0;
  const auto [end, ec] = std::from_chars(t.data(), t.data() + t.size(), i);
  if (ec != std::errc() || end != t.data() + t.size())
    return Status::InvalidArgument(At(line) + "'" + EscapeForMessage(t) + "' is not a " + what + " index");
  const long long resolved = i > 0 ? i - 1 : static_cast<long long>(defined) + i;
  if (i == 0 || resolved < 0 || resolved >= static_cast<long long>(defined))
    return Status::InvalidArgument(At(line) + what + " index " + std::to_string(i) + " is out of range (" +
                                   std::to_string(defined) + " " + plural + " so far)");
  return static_cast<uint32_t>(resolved);
}

}  // namespace

StatusOr<Mesh> ParseObj(std::string_view text, std::string_view name, std::vector<std::string>* warnings,
                        const ImportLimits& limits) {
  Mesh mesh;
  mesh.name = std::string(name);
  std::vector<Eigen::Vector3f> file_normals;
  size_t texcoords = 0;
  std::vector<Eigen::Vector3f> normal_sum;   // per vertex, sum of the vn its corners name
  std::vector<uint32_t> normal_first;        // the first vn index a vertex got (+1; 0 = none)
  size_t conflicting = 0, ignored = 0;
  std::string first_ignored;
  bool any_corner_normal = false;
  std::vector<uint32_t> polygon;
  std::vector<std::string_view> tokens;

  auto process = [&](std::string_view statement, size_t line_number) -> Status {
    Tokens(statement, tokens);
    if (tokens.empty()) return Status::Ok();
    const std::string_view kind = tokens[0];
    if (kind == "v") {
      if (mesh.positions.size() >= limits.max_mesh_vertices)
        return Status::ResourceExhausted(At(line_number) + OverImportLimitCount(mesh.positions.size() + 1, "vertices",
                                                                                "max_mesh_vertices",
                                                                                limits.max_mesh_vertices));
      auto v = ParseVector(tokens, line_number);
      if (!v.ok()) return v.status();
      mesh.positions.push_back(*v);
    } else if (kind == "vn") {
      auto n = ParseVector(tokens, line_number);
      if (!n.ok()) return n.status();
      file_normals.push_back(*n);
    } else if (kind == "vt") {
      ++texcoords;
    } else if (kind == "f") {
      if (tokens.size() < 4)
        return Status::InvalidArgument(At(line_number) + "a face needs at least 3 vertices, got " +
                                       std::to_string(tokens.size() - 1));
      normal_sum.resize(mesh.positions.size(), Eigen::Vector3f::Zero());
      normal_first.resize(mesh.positions.size(), 0);
      polygon.clear();
      for (size_t c = 1; c < tokens.size(); ++c) {
        const std::string_view corner = tokens[c];
        const size_t s1 = corner.find('/');
        auto v = ResolveIndex(corner.substr(0, s1), mesh.positions.size(), "vertex", "vertices", line_number);
        if (!v.ok()) return v.status();
        if (s1 != std::string_view::npos) {
          const std::string_view rest = corner.substr(s1 + 1);
          const size_t s2 = rest.find('/');
          const std::string_view t = rest.substr(0, s2);
          if (!t.empty()) {
            auto ti = ResolveIndex(t, texcoords, "texture coordinate", "texture coordinates", line_number);
            if (!ti.ok()) return ti.status();
          }
          if (s2 != std::string_view::npos) {
            auto ni = ResolveIndex(rest.substr(s2 + 1), file_normals.size(), "normal", "normals", line_number);
            if (!ni.ok()) return ni.status();
            any_corner_normal = true;
            const Eigen::Vector3f& n = file_normals[*ni];
            if (normal_first[*v] == 0) normal_first[*v] = *ni + 1;
            else if (normal_first[*v] != *ni + 1 && !file_normals[normal_first[*v] - 1].isApprox(n)) ++conflicting;
            normal_sum[*v] += n.normalized();
          }
        }
        polygon.push_back(*v);
      }
      for (size_t i = 1; i + 1 < polygon.size(); ++i)
        mesh.triangles.insert(mesh.triangles.end(), {polygon[0], polygon[i], polygon[i + 1]});
    } else if (kind == "o" || kind == "g" || kind == "s" || kind == "usemtl" || kind == "mtllib" || kind == "l" ||
               kind == "p" || kind == "vp") {
      // Grouping, smoothing, materials, lines and points do not change the rest mesh.
    } else if (ignored++ == 0) {
      first_ignored = At(line_number) + "'" + EscapeForMessage(kind) + "'";
    }
    return Status::Ok();
  };

  // Lines, with comments cut and trailing-backslash continuations joined.
  std::string joined;
  size_t joined_line = 0, line_number = 0;
  for (size_t pos = 0; pos < text.size();) {
    const size_t eol = std::min(text.find('\n', pos), text.size());
    std::string_view line = text.substr(pos, eol - pos);
    pos = eol + 1;
    ++line_number;
    if (const size_t hash = line.find('#'); hash != std::string_view::npos) line = line.substr(0, hash);
    while (!line.empty() && IsSpace(line.back())) line.remove_suffix(1);
    if (!line.empty() && line.back() == '\\') {
      if (joined.empty()) joined_line = line_number;
      joined.append(line.substr(0, line.size() - 1)).push_back(' ');
      continue;
    }
    if (joined.empty()) {
      ARMATURE_RETURN_IF_ERROR(process(line, line_number));
    } else {
      joined.append(line);
      ARMATURE_RETURN_IF_ERROR(process(joined, joined_line));
      joined.clear();
    }
  }
  if (!joined.empty()) ARMATURE_RETURN_IF_ERROR(process(joined, joined_line));
  if (mesh.positions.empty()) return Status::InvalidArgument("OBJ has no vertices ('v' lines)");

  if (any_corner_normal) {
    normal_sum.resize(mesh.positions.size(), Eigen::Vector3f::Zero());
    const auto computed = ComputeVertexNormals(mesh.positions, mesh.triangles);
    size_t filled = 0;
    mesh.normals.resize(mesh.positions.size());
    for (size_t v = 0; v < mesh.positions.size(); ++v) {
      const float len = normal_sum[v].norm();
      if (len > 0) {
        mesh.normals[v] = normal_sum[v] / len;
      } else {
        mesh.normals[v] = computed[v];
        ++filled;
      }
    }
    if (warnings && conflicting > 0)
      warnings->push_back(std::to_string(conflicting) +
                          " face corners give a vertex a different normal than another corner; normals averaged");
    if (warnings && filled > 0)
      warnings->push_back(std::to_string(filled) + " vertices have no 'vn' in any face; normals computed");
  } else {
    mesh.normals = ComputeVertexNormals(mesh.positions, mesh.triangles);
  }
  if (warnings && ignored > 0)
    warnings->push_back(std::to_string(ignored) + " unsupported statements ignored (first: " + first_ignored + ")");
  ARMATURE_RETURN_IF_ERROR(FinalizeMesh(mesh, warnings));
  return mesh;
}

}  // namespace armature
