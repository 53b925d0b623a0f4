#include "armature/engine/deform/laplacian_editor.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <optional>
#include <string>
#include <vector>

#include "../testing/deformation_test_util.h"
#include "../testing/generated_meshes.h"
#include "../testing/scipy_reference.h"

namespace armature {
namespace {

using fixtures::AsRows;
using fixtures::GeneratedMesh;
using fixtures::Interleave;
using fixtures::MakeGrid;
using fixtures::ScipyAvailable;

constexpr int kSide = 33;  // 33 × 33 = 1089 vertices

uint32_t GridVertex(int i, int j) { return static_cast<uint32_t>(j * kSide + i); }

std::vector<uint32_t> GridBoundary(int side = kSide) {
  std::vector<uint32_t> b;
  for (int j = 0; j < side; ++j)
    for (int i = 0; i < side; ++i)
      if (i == 0 || j == 0 || i == side - 1 || j == side - 1) b.push_back(static_cast<uint32_t>(j * side + i));
  return b;
}

// The centre vertex dragged, the border held.
DeformationConstraints CentreHandleHeldBorder() {
  DeformationConstraints c;
  c.handles = {GridVertex(16, 16)};
  c.fixed = GridBoundary();
  return c;
}

// A wavy 33 × 33 sheet on [−1,1]²: the detail the edit should keep.
GeneratedMesh WavySheet() {
  GeneratedMesh m = MakeGrid(kSide, kSide, 2, 2);
  for (Eigen::Index v = 0; v < m.positions.rows(); ++v)
    m.positions(v, 2) = 0.1 * std::sin(3 * m.positions(v, 0)) * std::cos(2 * m.positions(v, 1));
  return m;
}

std::shared_ptr<const LaplacianModel> Model(const GeneratedMesh& m, LaplacianWeights weights) {
  LaplacianModelOptions options;
  options.weights = weights;
  auto model = BuildLaplacianModel(m.positions, m.triangles, options);
  EXPECT_TRUE(model.ok()) << model.status().message();
  return model.ok() ? *model : nullptr;
}

// Handle targets: the rest positions of `handles` moved by `offset`.
Eigen::MatrixX3d Moved(const LaplacianModel& model, const std::vector<uint32_t>& handles, Eigen::RowVector3d offset) {
  Eigen::MatrixX3d t(static_cast<Eigen::Index>(handles.size()), 3);
  for (size_t k = 0; k < handles.size(); ++k)
    t.row(static_cast<Eigen::Index>(k)) = model.rest_positions.row(handles[k]) + offset;
  return t;
}

// The same constraints solved through a handle basis and by back-substitution.
struct BasisAndBackSubstitution {
  StatusOr<DeformationSolver> basis, back;
};
BasisAndBackSubstitution BothDragUpdates(std::shared_ptr<const LaplacianModel> model, const DeformationConstraints& c) {
  DeformationSolverOptions basis, back;
  basis.drag_update = DragUpdate::kHandleBasis;
  back.drag_update = DragUpdate::kBackSubstitution;
  return {DeformationSolver::Create(model, c, basis), DeformationSolver::Create(model, c, back)};
}

Eigen::MatrixX3d SolveOrDie(const DeformationSolver& solver, const Eigen::MatrixX3d& targets) {
  std::vector<double> out(3 * solver.model().vertex_count());
  const Status st = solver.Solve(Interleave(targets), out);
  EXPECT_TRUE(st.ok()) << st.message();
  return AsRows(out);
}

// --- SciPy reference ------------------------------------------------------

// Solves the same problem with tests/reference/laplacian_reference.py in a
// scratch directory removed afterwards. nullopt when it could not run.
std::optional<Eigen::MatrixX3d> ScipyReference(const GeneratedMesh& mesh, LaplacianWeights weights,
                                               const DeformationConstraints& c, const Eigen::MatrixX3d& targets) {
  const auto dir =
      std::filesystem::temp_directory_path() /
      ("armature_laplacian_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
       std::to_string(::getpid()));
  auto result = fixtures::LaplacianScipyReference(mesh, std::string(LaplacianWeightsName(weights)), c.fixed,
                                                  c.region_of_interest, c.handles, targets, dir);
  std::filesystem::remove_all(dir);
  return result;
}

void ExpectMatchesScipy(LaplacianWeights weights, const DeformationConstraints& c, const Eigen::RowVector3d& drag) {
  if (!ScipyAvailable()) GTEST_SKIP() << "/usr/bin/python3 with scipy is not installed (scripts/setup.sh test)";
  const GeneratedMesh mesh = WavySheet();
  const auto model = Model(mesh, weights);
  ASSERT_TRUE(model);
  const Eigen::MatrixX3d targets = Moved(*model, c.handles, drag);
  const auto reference = ScipyReference(mesh, weights, c, targets);
  ASSERT_TRUE(reference.has_value()) << "the SciPy reference script failed";
  for (DragUpdate update : {DragUpdate::kHandleBasis, DragUpdate::kBackSubstitution}) {
    DeformationSolverOptions options;
    options.drag_update = update;
    auto solver = DeformationSolver::Create(model, c, options);
    ASSERT_TRUE(solver.ok()) << solver.status().message();
    const Eigen::MatrixX3d ours = SolveOrDie(*solver, targets);
    const double max_difference = (ours - *reference).cwiseAbs().maxCoeff();
    EXPECT_LT(max_difference, 1e-6);
    std::cout << "[ scipy    ] " << LaplacianWeightsName(weights)
              << (update == DragUpdate::kHandleBasis ? ", handle basis" : ", back-substitution")
              << ": max |engine − scipy| = " << max_difference << " over " << mesh.positions.rows()
              << " vertices, largest move " << (ours - mesh.positions).rowwise().norm().maxCoeff() << "\n";
    // Constraints are met exactly, not just to the solver's tolerance.
    for (size_t k = 0; k < c.handles.size(); ++k)
      EXPECT_EQ(ours.row(c.handles[k]), targets.row(static_cast<Eigen::Index>(k)));
    for (uint32_t v : c.fixed) EXPECT_EQ(ours.row(v), mesh.positions.row(v));
  }
}

TEST(LaplacianEditor, UniformHardMatchesScipy) {
  DeformationConstraints c;
  c.handles = {GridVertex(16, 16), GridVertex(17, 16), GridVertex(16, 17), GridVertex(10, 20)};
  c.fixed = GridBoundary();
  ExpectMatchesScipy(LaplacianWeights::kUniform, c, {0.15, -0.1, 0.4});
}

TEST(LaplacianEditor, CotangentHardWithRegionOfInterestMatchesScipy) {
  DeformationConstraints c;
  c.handles = {GridVertex(16, 16), GridVertex(18, 15)};
  c.fixed = {GridVertex(12, 12)};
  for (int j = 6; j <= 26; ++j)
    for (int i = 6; i <= 26; ++i)
      if ((i - 16) * (i - 16) + (j - 16) * (j - 16) <= 100) c.region_of_interest.push_back(GridVertex(i, j));
  ExpectMatchesScipy(LaplacianWeights::kCotangent, c, {-0.05, 0.1, 0.3});
}

// --- Soft constraints against a dense solve -------------------------------

TEST(LaplacianEditor, SoftConstraintsMatchDenseNormalEquations) {
  const GeneratedMesh mesh = MakeGrid(8, 7, 2, 1.5);
  for (LaplacianWeights weights : {LaplacianWeights::kUniform, LaplacianWeights::kCotangent}) {
    GeneratedMesh bumpy = mesh;
    fixtures::AddBump(bumpy, 0.2, 0.1, 0.3, 0.5);
    const auto model = Model(bumpy, weights);
    ASSERT_TRUE(model);
    DeformationConstraints c;
    c.mode = ConstraintMode::kSoft;
    c.soft_weight = 2.5;
    c.handles = {20, 35};
    c.fixed = {0, 7, 48, 55};
    auto solver = DeformationSolver::Create(model, c);
    ASSERT_TRUE(solver.ok()) << solver.status().message();
    Eigen::MatrixX3d targets(2, 3);
    targets << 0.1, 0.2, 0.8, -0.3, 0.4, -0.2;
    const Eigen::MatrixX3d ours = SolveOrDie(*solver, targets);

    // [L; w·I_c]·V′ = [δ; w·U] as one dense least-squares problem.
    const Eigen::Index n = bumpy.positions.rows(), nc = 6;
    Eigen::MatrixXd a = Eigen::MatrixXd::Zero(n + nc, n);
    Eigen::MatrixXd b(n + nc, 3);
    a.topRows(n) = Eigen::MatrixXd(model->laplacian);
    b.topRows(n) = model->laplacian * bumpy.positions;
    const std::vector<uint32_t> rows = {20, 35, 0, 7, 48, 55};
    for (Eigen::Index k = 0; k < nc; ++k) {
      a(n + k, rows[static_cast<size_t>(k)]) = c.soft_weight;
      b.row(n + k) = c.soft_weight * (k < 2 ? Eigen::RowVector3d(targets.row(k))
                                            : Eigen::RowVector3d(bumpy.positions.row(rows[static_cast<size_t>(k)])));
    }
    const Eigen::MatrixXd dense = (a.transpose() * a).ldlt().solve(a.transpose() * b);
    EXPECT_LT((ours - dense).cwiseAbs().maxCoeff(), 1e-9) << LaplacianWeightsName(weights);
    // Soft handles are pulled toward, not onto, their targets.
    EXPECT_GT((ours.row(20) - targets.row(0)).norm(), 1e-3);
    EXPECT_LT((ours.row(20) - targets.row(0)).norm(), (bumpy.positions.row(20) - targets.row(0)).norm());
  }
}

// --- Region of interest, drag strategies, precision -----------------------

TEST(LaplacianEditor, RegionOfInterestEqualsFixingEverythingOutside) {
  const GeneratedMesh mesh = WavySheet();
  const auto model = Model(mesh, LaplacianWeights::kUniform);
  DeformationConstraints local;
  local.handles = {GridVertex(16, 16)};
  for (int j = 10; j <= 22; ++j)
    for (int i = 10; i <= 22; ++i) local.region_of_interest.push_back(GridVertex(i, j));
  DeformationConstraints whole;
  whole.handles = local.handles;
  for (uint32_t v = 0; v < mesh.positions.rows(); ++v) {
    const int i = static_cast<int>(v) % kSide, j = static_cast<int>(v) / kSide;
    if (i < 10 || i > 22 || j < 10 || j > 22) whole.fixed.push_back(v);
  }
  auto a = DeformationSolver::Create(model, local);
  auto b = DeformationSolver::Create(model, whole);
  ASSERT_TRUE(a.ok() && b.ok());
  EXPECT_EQ(a->unknown_count(), 13u * 13u - 1u);
  const Eigen::MatrixX3d targets = Moved(*model, local.handles, {0.1, 0.2, 0.5});
  const Eigen::MatrixX3d ra = SolveOrDie(*a, targets), rb = SolveOrDie(*b, targets);
  EXPECT_LT((ra - rb).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(ra.row(GridVertex(9, 16)), mesh.positions.row(GridVertex(9, 16)));  // outside: untouched
  EXPECT_GT((ra.row(GridVertex(15, 16)) - mesh.positions.row(GridVertex(15, 16))).norm(), 0.1);
}

TEST(LaplacianEditor, HandleBasisAndBackSubstitutionAgree) {
  const GeneratedMesh mesh = WavySheet();
  const auto model = Model(mesh, LaplacianWeights::kCotangent);
  for (ConstraintMode mode : {ConstraintMode::kHard, ConstraintMode::kSoft}) {
    DeformationConstraints c;
    c.mode = mode;
    c.handles = {GridVertex(16, 16), GridVertex(5, 25), GridVertex(28, 3)};
    c.fixed = GridBoundary();
    auto [a, b] = BothDragUpdates(model, c);
    ASSERT_TRUE(a.ok() && b.ok());
    EXPECT_TRUE(a->uses_handle_basis());
    EXPECT_FALSE(b->uses_handle_basis());
    EXPECT_EQ(a->handle_basis_bytes(), a->unknown_count() * 3 * sizeof(double));
    EXPECT_EQ(b->handle_basis_bytes(), 0u);
    // Several drags through one factorization, as in a session.
    for (double t : {0.0, 0.3, -0.7, 1.0}) {
      const Eigen::MatrixX3d targets = Moved(*model, c.handles, {0.2 * t, -0.1 * t, 0.5 * t});
      const Eigen::MatrixX3d ra = SolveOrDie(*a, targets), rb = SolveOrDie(*b, targets);
      EXPECT_LT((ra - rb).cwiseAbs().maxCoeff(), 1e-10);
      if (t == 0.0) EXPECT_LT((ra - mesh.positions).cwiseAbs().maxCoeff(), 1e-12);  // rest in, rest out
    }
  }
}

// A basis large enough to be split across the worker pool (≥ 2^17 entries):
// every row must be updated once, whatever the split.
TEST(LaplacianEditor, LargeHandleBasisSplitAcrossCoresAgreesWithBackSubstitution) {
  constexpr int side = 121;
  const GeneratedMesh mesh = MakeGrid(side, side, 2, 2);
  const auto model = Model(mesh, LaplacianWeights::kUniform);
  DeformationConstraints c;
  for (int k = 0; k < 12; ++k) c.handles.push_back(static_cast<uint32_t>((10 + 8 * k) * side + 20 + 7 * k));
  c.fixed = GridBoundary(side);
  auto [a, b] = BothDragUpdates(model, c);
  ASSERT_TRUE(a.ok() && b.ok());
  ASSERT_GE(a->unknown_count() * c.handles.size(), size_t{1} << 17);
  // Each handle moves its own way, so a row updated twice or skipped shows.
  Eigen::MatrixX3d targets(static_cast<Eigen::Index>(c.handles.size()), 3);
  for (size_t k = 0; k < c.handles.size(); ++k)
    targets.row(static_cast<Eigen::Index>(k)) =
        model->rest_positions.row(c.handles[k]) + Eigen::RowVector3d(0.01 * k, -0.02 * (k % 3), 0.1 + 0.03 * k);
  const Eigen::MatrixX3d ra = SolveOrDie(*a, targets), rb = SolveOrDie(*b, targets);
  EXPECT_LT((ra - rb).cwiseAbs().maxCoeff(), 1e-10);
  EXPECT_GT((ra - mesh.positions).cwiseAbs().maxCoeff(), 0.1);
}

TEST(LaplacianEditor, FloatSpansMatchDoubles) {
  const GeneratedMesh mesh = WavySheet();
  const auto model = Model(mesh, LaplacianWeights::kUniform);
  const DeformationConstraints c = CentreHandleHeldBorder();
  auto solver = DeformationSolver::Create(model, c);
  ASSERT_TRUE(solver.ok());
  const Eigen::MatrixX3d targets = Moved(*model, c.handles, {0.1, 0.1, 0.3});
  const Eigen::MatrixX3d d = SolveOrDie(*solver, targets);
  const std::vector<float> target_f = {static_cast<float>(targets(0, 0)), static_cast<float>(targets(0, 1)),
                                       static_cast<float>(targets(0, 2))};
  std::vector<float> out(3 * mesh.positions.rows());
  ASSERT_TRUE(solver->Solve(std::span<const float>(target_f), std::span<float>(out)).ok());
  for (size_t i = 0; i < out.size(); ++i) EXPECT_NEAR(out[i], d(static_cast<Eigen::Index>(i / 3), i % 3), 1e-5);
  // Double handles into floats (an API answer): the double result, rounded once.
  const std::vector<double> target_d = Interleave(targets);
  ASSERT_TRUE(solver->Solve(std::span<const double>(target_d), std::span<float>(out)).ok());
  for (size_t i = 0; i < out.size(); ++i)
    EXPECT_EQ(out[i], static_cast<float>(d(static_cast<Eigen::Index>(i / 3), i % 3))) << i;
}

TEST(LaplacianEditor, OneShotDeformMatchesSolver) {
  const GeneratedMesh mesh = WavySheet();
  const auto model = Model(mesh, LaplacianWeights::kUniform);
  const DeformationConstraints c = CentreHandleHeldBorder();
  const Eigen::MatrixX3d targets = Moved(*model, c.handles, {0, 0, 0.5});
  auto once = DeformLaplacian(model, c, Interleave(targets));
  ASSERT_TRUE(once.ok()) << once.status().message();
  auto solver = DeformationSolver::Create(model, c);
  ASSERT_TRUE(solver.ok());
  EXPECT_LT((*once - SolveOrDie(*solver, targets)).cwiseAbs().maxCoeff(), 1e-10);
}

// --- Detail preservation --------------------------------------------------

// Heights of `bump` vertices above the plane fitted (least squares) through
// the `base` ring, measured along that plane's normal, oriented upward.
Eigen::VectorXd HeightsAboveBase(const Eigen::MatrixX3d& p, const std::vector<uint32_t>& bump,
                                 const std::vector<uint32_t>& base) {
  Eigen::MatrixX3d ring(static_cast<Eigen::Index>(base.size()), 3);
  for (size_t k = 0; k < base.size(); ++k) ring.row(static_cast<Eigen::Index>(k)) = p.row(base[k]);
  const Eigen::RowVector3d centre = ring.colwise().mean();
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(ring.rowwise() - centre, Eigen::ComputeThinV);
  Eigen::RowVector3d normal = svd.matrixV().col(2).transpose();
  if (normal.z() < 0) normal = -normal;
  Eigen::VectorXd h(static_cast<Eigen::Index>(bump.size()));
  for (size_t k = 0; k < bump.size(); ++k) h(static_cast<Eigen::Index>(k)) = (p.row(bump[k]) - centre).dot(normal);
  return h;
}

// A bump on a plane, with a handle beside it lifted: the bump rides along
// and keeps its height profile over its (now tilted) base, where a solver
// that lost δ would flatten it.
TEST(LaplacianEditor, BumpKeepsItsShapeWhenANeighbourIsDragged) {
  GeneratedMesh mesh = MakeGrid(41, 41, 2, 2);
  const double bump_height = 0.2, sigma = 0.12;
  fixtures::AddBump(mesh, -0.3, 0.0, bump_height, sigma);
  std::vector<uint32_t> bump, base;
  DeformationConstraints c;
  for (uint32_t v = 0; v < mesh.positions.rows(); ++v) {
    const double x = mesh.positions(v, 0), y = mesh.positions(v, 1), r = std::hypot(x + 0.3, y);
    if (r < 2.5 * sigma) bump.push_back(v);
    if (r >= 2.5 * sigma && r < 3.2 * sigma) base.push_back(v);
    if (std::hypot(x - 0.25, y) < 0.08) c.handles.push_back(v);
    if (std::abs(x) > 0.99 || std::abs(y) > 0.99) c.fixed.push_back(v);
  }
  const Eigen::VectorXd rest_heights = HeightsAboveBase(mesh.positions, bump, base);
  const double flattened = std::sqrt(rest_heights.squaredNorm() / static_cast<double>(bump.size())) / bump_height;

  for (LaplacianWeights weights : {LaplacianWeights::kUniform, LaplacianWeights::kCotangent}) {
    const auto model = Model(mesh, weights);
    auto solver = DeformationSolver::Create(model, c);
    ASSERT_TRUE(solver.ok()) << solver.status().message();
    const Eigen::MatrixX3d out = SolveOrDie(*solver, Moved(*model, c.handles, {0, 0, 0.25}));
    double lift = 0;
    for (uint32_t v : bump) lift += (out(v, 2) - mesh.positions(v, 2)) / static_cast<double>(bump.size());
    const Eigen::VectorXd heights = HeightsAboveBase(out, bump, base);
    const double error =
        std::sqrt((heights - rest_heights).squaredNorm() / static_cast<double>(bump.size())) / bump_height;
    std::cout << "[ bump     ] " << LaplacianWeightsName(weights) << ": bump lifted by " << lift
              << ", height profile RMS error " << error << " of the bump height (a flattened bump: " << flattened
              << ")\n";
    EXPECT_GT(lift, 0.05);  // the edit reached the bump
    // Laplacian coordinates do not rotate with the tilting base (ARAP does),
    // so a few % remain; losing the detail would cost ~29%.
    EXPECT_LT(error, 0.08);
  }
}

// A vertex no triangle uses (common in OBJ files) needs no constraint: it stays put.
TEST(LaplacianEditor, UnusedVerticesStayPut) {
  GeneratedMesh mesh = MakeGrid(5, 5, 1, 1);
  mesh.positions.conservativeResize(26, 3);
  mesh.positions.row(25) << 7, 8, 9;
  const auto model = Model(mesh, LaplacianWeights::kCotangent);
  DeformationConstraints c;
  c.handles = {12};
  c.fixed = {0, 4, 20, 24};
  auto solver = DeformationSolver::Create(model, c);
  ASSERT_TRUE(solver.ok()) << solver.status().message();
  EXPECT_EQ(solver->unknown_count(), 20u);
  const Eigen::MatrixX3d out = SolveOrDie(*solver, Moved(*model, c.handles, {0, 0, 1}));
  EXPECT_EQ(out.row(25), Eigen::RowVector3d(7, 8, 9));
  EXPECT_GT(out(11, 2), 0.1);
}

// --- Bad input ------------------------------------------------------------

Status CreateStatus(const std::shared_ptr<const LaplacianModel>& model, const DeformationConstraints& c,
                    const DeformationSolverOptions& options = {}) {
  return DeformationSolver::Create(model, c, options).status();
}

TEST(LaplacianEditor, RejectsBadConstraintsWithNamedField) {
  const auto model = Model(WavySheet(), LaplacianWeights::kUniform);
  DeformationConstraints c;
  c.handles = {5, 6, 1200};
  c.fixed = GridBoundary();
  Status st = CreateStatus(model, c);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(), "handles[2].index 1200 is out of range (mesh has 1089 vertices)");

  c.handles = {500, 0};  // vertex 0 is a boundary (fixed) vertex
  st = CreateStatus(model, c);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(), "handles[1].index 0 is also fixed (fixed[0]); a vertex is either dragged or held");

  c.handles = {500, 501, 500};
  EXPECT_EQ(CreateStatus(model, c).message(), "handles[2].index 500 repeats handles[0].index");

  c.handles = {500};
  c.fixed = {2000};
  EXPECT_EQ(CreateStatus(model, c).message(), "fixed[0] 2000 is out of range (mesh has 1089 vertices)");

  c.fixed = {};
  c.region_of_interest = {499, 501};
  EXPECT_EQ(CreateStatus(model, c).message(), "handles[0].index 500 lies outside the region of interest");
  c.region_of_interest = {500, 1089};
  EXPECT_EQ(CreateStatus(model, c).message(), "region_of_interest[1] 1089 is out of range (mesh has 1089 vertices)");

  c.region_of_interest = {};
  c.mode = ConstraintMode::kSoft;
  c.soft_weight = 0;
  EXPECT_EQ(CreateStatus(model, c).code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(CreateStatus(nullptr, c).code(), StatusCode::kInvalidArgument);
}

TEST(LaplacianEditor, RejectsAComponentWithoutConstraints) {
  const GeneratedMesh grid = MakeGrid(5, 5, 1, 1);
  const GeneratedMesh two = fixtures::Concatenate(grid, grid, {3, 0, 0});
  const auto model = Model(two, LaplacianWeights::kUniform);
  DeformationConstraints c;
  c.handles = {12};
  c.fixed = {0};
  const Status st = CreateStatus(model, c);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(),
            "connected component 1 (25 vertices, including vertex 25) has no handle or fixed vertex: its position is "
            "undetermined (singular system); add a handle or fixed vertex on it");
  // With nothing at all: the first component is named.
  EXPECT_NE(CreateStatus(model, {}).message().find("connected component 0"), std::string::npos);
  // Anchoring the second piece, or leaving it out of the region, solves it.
  c.fixed = {0, 30};
  EXPECT_TRUE(CreateStatus(model, c).ok());
  c.fixed = {0};
  for (uint32_t v = 0; v < 25; ++v) c.region_of_interest.push_back(v);
  EXPECT_TRUE(CreateStatus(model, c).ok());
}

TEST(LaplacianEditor, RejectsBadHandlePositionsAndSpans) {
  const auto model = Model(WavySheet(), LaplacianWeights::kUniform);
  DeformationConstraints c;
  c.handles = {500, 501};
  c.fixed = GridBoundary();
  auto solver = DeformationSolver::Create(model, c);
  ASSERT_TRUE(solver.ok());
  std::vector<double> out(3 * 1089);
  std::vector<double> targets = {0, 0, 0, 1, NAN, 0};
  EXPECT_EQ(solver->Solve(targets, out).message(), "handles[1].position is not finite");
  targets.pop_back();
  EXPECT_EQ(solver->Solve(targets, out).message(),
            "handle_positions: expected 3 values per handle (6 for 2 handles), got 5");
  targets = {0, 0, 0, 1, 1, 1};
  std::vector<double> short_out(10);
  EXPECT_EQ(solver->Solve(targets, short_out).code(), StatusCode::kInvalidArgument);
}

TEST(LaplacianEditor, AccountsMemoryAndEnforcesTheLimit) {
  const auto model = Model(WavySheet(), LaplacianWeights::kUniform);
  const DeformationConstraints c = CentreHandleHeldBorder();
  auto solver = DeformationSolver::Create(model, c);
  ASSERT_TRUE(solver.ok());
  // The factor has at least one entry per unknown (the diagonal D) and the
  // strict lower triangle of L holds at least the matrix's own pattern.
  EXPECT_GT(solver->factorization_bytes(), solver->unknown_count() * sizeof(double) * 5);
  EXPECT_GE(solver->memory_bytes(), solver->factorization_bytes() + solver->handle_basis_bytes());
  EXPECT_GT(model->memory_bytes(), 1089u * 3 * sizeof(double) * 2);

  DeformationSolverOptions tight;
  tight.max_factorization_bytes = solver->factorization_bytes() - 1;
  const Status st = CreateStatus(model, c, tight);
  EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
  EXPECT_NE(st.message().find("the factorization needs"), std::string::npos) << st.message();

  DeformationSolverOptions no_basis;
  no_basis.drag_update = DragUpdate::kHandleBasis;
  no_basis.max_handle_basis_bytes = 8;
  EXPECT_EQ(CreateStatus(model, c, no_basis).code(), StatusCode::kResourceExhausted);
  no_basis.drag_update = DragUpdate::kAuto;  // auto falls back to back-substitution
  auto fallback = DeformationSolver::Create(model, c, no_basis);
  ASSERT_TRUE(fallback.ok());
  EXPECT_FALSE(fallback->uses_handle_basis());
}

}  // namespace
}  // namespace armature
