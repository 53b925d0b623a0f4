#include "armature/engine/io/obj/obj.h"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

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
StatusOr<uint32_t> ResolveIndex(std::string_view t, size_t defined, const char* what, const char* plural, size_t line) {
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

// Calls `statement` on each line, with comments cut and trailing-backslash
// continuations joined (numbered by their first line).
template <class Statement>
Status ForEachStatement(std::string_view text, Statement statement) {
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
      ARMATURE_RETURN_IF_ERROR(statement(line, line_number));
    } else {
      joined.append(line);
      ARMATURE_RETURN_IF_ERROR(statement(joined, joined_line));
      joined.clear();
    }
  }
  if (!joined.empty()) ARMATURE_RETURN_IF_ERROR(statement(joined, joined_line));
  return Status::Ok();
}

// One OBJ parse: statements in, in order; the mesh out, with its normals.
class ObjReader {
 public:
  ObjReader(std::string_view name, const ImportLimits& limits) : limits_(limits) { mesh_.name = std::string(name); }

  Status Statement(std::string_view statement, size_t line) {
    Tokens(statement, tokens_);
    if (tokens_.empty()) return Status::Ok();
    const std::string_view kind = tokens_[0];
    if (kind == "v") {
      if (mesh_.positions.size() >= limits_.max_mesh_vertices)
        return Status::ResourceExhausted(At(line) + OverImportLimitCount(mesh_.positions.size() + 1, "vertices",
                                                                         "max_mesh_vertices",
                                                                         limits_.max_mesh_vertices));
      ARMATURE_ASSIGN_OR_RETURN(const Eigen::Vector3f v, ParseVector(tokens_, line));
      mesh_.positions.push_back(v);
    } else if (kind == "vn") {
      ARMATURE_ASSIGN_OR_RETURN(const Eigen::Vector3f n, ParseVector(tokens_, line));
      file_normals_.push_back(n);
    } else if (kind == "vt") {
      ++texcoords_;
    } else if (kind == "f") {
      return Face(line);
    } else if (kind == "o" || kind == "g" || kind == "s" || kind == "usemtl" || kind == "mtllib" || kind == "l" ||
               kind == "p" || kind == "vp") {
      // Grouping, smoothing, materials, lines and points do not change the rest mesh.
    } else if (ignored_++ == 0) {
      first_ignored_ = At(line) + "'" + EscapeForMessage(kind) + "'";
    }
    return Status::Ok();
  }

  bool empty() const { return mesh_.positions.empty(); }

  // The mesh with its vertex normals: the averaged 'vn' its corners name,
  // else computed from the triangles; warnings for what was averaged,
  // computed or ignored.
  Mesh Finish(std::vector<std::string>* warnings) {
    if (any_corner_normal_) {
      normal_sum_.resize(mesh_.positions.size(), Eigen::Vector3f::Zero());
      const auto computed = ComputeVertexNormals(mesh_.positions, mesh_.triangles);
      size_t filled = 0;
      mesh_.normals.resize(mesh_.positions.size());
      for (size_t v = 0; v < mesh_.positions.size(); ++v) {
        const float len = normal_sum_[v].norm();
        if (len > 0) {
          mesh_.normals[v] = normal_sum_[v] / len;
        } else {
          mesh_.normals[v] = computed[v];
          ++filled;
        }
      }
      if (warnings && conflicting_ > 0)
        warnings->push_back(std::to_string(conflicting_) +
                            " face corners give a vertex a different normal than another corner; normals averaged");
      if (warnings && filled > 0)
        warnings->push_back(std::to_string(filled) + " vertices have no 'vn' in any face; normals computed");
    } else {
      mesh_.normals = ComputeVertexNormals(mesh_.positions, mesh_.triangles);
    }
    if (warnings && ignored_ > 0)
      warnings->push_back(std::to_string(ignored_) + " unsupported statements ignored (first: " + first_ignored_ + ")");
    return std::move(mesh_);
  }

 private:
  // An 'f' statement: a polygon, fanned into triangles.
  Status Face(size_t line) {
    if (tokens_.size() < 4)
      return Status::InvalidArgument(At(line) + "a face needs at least 3 vertices, got " +
                                     std::to_string(tokens_.size() - 1));
    normal_sum_.resize(mesh_.positions.size(), Eigen::Vector3f::Zero());
    normal_first_.resize(mesh_.positions.size(), 0);
    polygon_.clear();
    for (size_t c = 1; c < tokens_.size(); ++c) {
      ARMATURE_ASSIGN_OR_RETURN(const uint32_t v, Corner(tokens_[c], line));
      polygon_.push_back(v);
    }
    for (size_t i = 1; i + 1 < polygon_.size(); ++i)
      mesh_.triangles.insert(mesh_.triangles.end(), {polygon_[0], polygon_[i], polygon_[i + 1]});
    return Status::Ok();
  }

  // A face corner "v", "v/t", "v//n" or "v/t/n": its vertex; its normal summed into the vertex's.
  StatusOr<uint32_t> Corner(std::string_view corner, size_t line) {
    const size_t s1 = corner.find('/');
    ARMATURE_ASSIGN_OR_RETURN(const uint32_t v,
                              ResolveIndex(corner.substr(0, s1), mesh_.positions.size(), "vertex", "vertices", line));
    if (s1 == std::string_view::npos) return v;
    const std::string_view rest = corner.substr(s1 + 1);
    const size_t s2 = rest.find('/');
    const std::string_view t = rest.substr(0, s2);
    if (!t.empty())
      ARMATURE_RETURN_IF_ERROR(ResolveIndex(t, texcoords_, "texture coordinate", "texture coordinates", line).status());
    if (s2 == std::string_view::npos) return v;
    ARMATURE_ASSIGN_OR_RETURN(const uint32_t ni,
                              ResolveIndex(rest.substr(s2 + 1), file_normals_.size(), "normal", "normals", line));
    any_corner_normal_ = true;
    const Eigen::Vector3f& n = file_normals_[ni];
    if (normal_first_[v] == 0)
      normal_first_[v] = ni + 1;
    else if (normal_first_[v] != ni + 1 && !file_normals_[normal_first_[v] - 1].isApprox(n))
      ++conflicting_;
    normal_sum_[v] += n.normalized();
    return v;
  }

  const ImportLimits& limits_;
  Mesh mesh_;
  std::vector<Eigen::Vector3f> file_normals_;
  size_t texcoords_ = 0;
  std::vector<Eigen::Vector3f> normal_sum_;  // per vertex, sum of the vn its corners name
  std::vector<uint32_t> normal_first_;       // the first vn index a vertex got (+1; 0 = none)
  size_t conflicting_ = 0, ignored_ = 0;
  std::string first_ignored_;
  bool any_corner_normal_ = false;
  std::vector<uint32_t> polygon_;
  std::vector<std::string_view> tokens_;
};

}  // namespace

StatusOr<Mesh> ParseObj(std::string_view text, std::string_view name, std::vector<std::string>* warnings,
                        const ImportLimits& limits) {
  ObjReader reader(name, limits);
  ARMATURE_RETURN_IF_ERROR(ForEachStatement(
      text, [&reader](std::string_view statement, size_t line) { return reader.Statement(statement, line); }));
  if (reader.empty()) return Status::InvalidArgument("OBJ has no vertices ('v' lines)");
  Mesh mesh = reader.Finish(warnings);
  ARMATURE_RETURN_IF_ERROR(FinalizeMesh(mesh, warnings));
  return mesh;
}

}  // namespace armature
