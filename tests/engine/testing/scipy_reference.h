// The SciPy reference for the Laplacian editor, shared by the engine tests and
// the DeformService integration tests: tests/reference/laplacian_reference.py
// solves the hard-constrained problem as a KKT system through SciPy's SuperLU
// (a different route from the engine's). Needs ARMATURE_TEST_DIR.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include "generated_meshes.h"

namespace armature::fixtures {

inline bool ScipyAvailable() { return std::system("/usr/bin/python3 -c 'import scipy.sparse' >/dev/null 2>&1") == 0; }

inline void WriteRows(const std::filesystem::path& path, const Eigen::MatrixXd& rows) {
  std::ofstream f(path);
  f.precision(17);
  for (Eigen::Index r = 0; r < rows.rows(); ++r) {
    for (Eigen::Index c = 0; c < rows.cols(); ++c) f << (c ? " " : "") << rows(r, c);
    f << "\n";
  }
}

inline void WriteIndices(const std::filesystem::path& path, const std::vector<uint32_t>& v, size_t per_line = 1) {
  std::ofstream f(path);
  for (size_t i = 0; i < v.size(); ++i) f << v[i] << ((i + 1) % per_line ? " " : "\n");
}

// Handle k goes to targets.row(k); `weights` is "uniform" or "cotangent"; an
// empty region of interest is the whole mesh. The script's files are written
// in `dir` (created; left to the caller). nullopt when the script failed.
inline std::optional<Eigen::MatrixX3d> LaplacianScipyReference(const GeneratedMesh& mesh, const std::string& weights,
                                                               const std::vector<uint32_t>& fixed,
                                                               const std::vector<uint32_t>& region_of_interest,
                                                               const std::vector<uint32_t>& handles,
                                                               const Eigen::MatrixX3d& targets,
                                                               const std::filesystem::path& dir) {
  std::filesystem::create_directories(dir);
  WriteRows(dir / "positions.txt", mesh.positions);
  WriteIndices(dir / "triangles.txt", mesh.triangles, 3);
  Eigen::MatrixXd handle_rows(targets.rows(), 4);
  for (Eigen::Index k = 0; k < targets.rows(); ++k)
    handle_rows.row(k) << handles[static_cast<size_t>(k)], targets.row(k);
  WriteRows(dir / "handles.txt", handle_rows);
  WriteIndices(dir / "fixed.txt", fixed);
  WriteIndices(dir / "roi.txt", region_of_interest);
  std::ofstream(dir / "weights.txt") << weights << "\n";
  const std::string command = "/usr/bin/python3 " ARMATURE_TEST_DIR "/reference/laplacian_reference.py " + dir.string();
  if (std::system(command.c_str()) != 0) return std::nullopt;
  std::ifstream in(dir / "result.txt");
  if (!in) return std::nullopt;
  Eigen::MatrixX3d r(mesh.positions.rows(), 3);
  for (Eigen::Index v = 0; v < r.rows(); ++v) in >> r(v, 0) >> r(v, 1) >> r(v, 2);
  if (!in) return std::nullopt;
  return r;
}

}  // namespace armature::fixtures
