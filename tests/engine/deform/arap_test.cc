#include "armature/engine/deform/arap.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <numbers>
#include <vector>

#include "armature/engine/deform/laplacian_editor.h"
#include "../testing/deformation_test_util.h"
#include "../testing/generated_meshes.h"

namespace armature {
namespace {

using fixtures::AsRows;
using fixtures::GeneratedMesh;
using fixtures::Interleave;

constexpr int kRings = 41, kSegments = 16;

// A bar: an open tube along x, 4 long, radius 0.5.
GeneratedMesh Bar() { return fixtures::MakeTube(kRings, kSegments, 0.5, 4.0); }

std::vector<uint32_t> Ring(int r) {
  std::vector<uint32_t> ring;
  for (int s = 0; s < kSegments; ++s) ring.push_back(static_cast<uint32_t>(r * kSegments + s));
  return ring;
}

std::shared_ptr<const LaplacianModel> CotangentModel(const GeneratedMesh& m) {
  LaplacianModelOptions options;
  options.weights = LaplacianWeights::kCotangent;
  auto model = BuildLaplacianModel(m.positions, m.triangles, options);
  EXPECT_TRUE(model.ok()) << model.status().message();
  return model.ok() ? *model : nullptr;
}

// The bar held at its start ring and dragged by its end ring.
DeformationConstraints HeldStartDraggedEnd() {
  DeformationConstraints c;
  c.fixed = Ring(0);
  c.handles = Ring(kRings - 1);
  return c;
}

Eigen::MatrixX3d Transformed(const Eigen::MatrixX3d& rest, const std::vector<uint32_t>& vertices,
                             const Eigen::Affine3d& motion) {
  Eigen::MatrixX3d t(static_cast<Eigen::Index>(vertices.size()), 3);
  for (size_t k = 0; k < vertices.size(); ++k)
    t.row(static_cast<Eigen::Index>(k)) = (motion * Eigen::Vector3d(rest.row(vertices[k]))).transpose();
  return t;
}

struct ArapRun {
  Eigen::MatrixX3d positions;
  ArapReport report;
};

ArapRun RunArap(const ArapSolver& solver, const Eigen::MatrixX3d& targets, const ArapOptions& options,
                std::vector<double> positions = {}) {
  positions.resize(3 * solver.model().vertex_count());
  auto report = solver.Solve(Interleave(targets), options, positions);
  EXPECT_TRUE(report.ok()) << report.status().message();
  return {AsRows(positions), report.ok() ? *report : ArapReport{}};
}

Eigen::MatrixX3d RunLaplacian(const std::shared_ptr<const LaplacianModel>& model, const DeformationConstraints& c,
                              const Eigen::MatrixX3d& targets) {
  auto out = DeformLaplacian(model, c, Interleave(targets));
  EXPECT_TRUE(out.ok()) << out.status().message();
  return out.ok() ? *out : Eigen::MatrixX3d();
}

// The local step against the textbook Procrustes solution by SVD:
// S = UΣVᵀ, R = V·diag(1, 1, det(VUᵀ))·Uᵀ.
TEST(Arap, NearestRotationMatchesSvdProcrustes) {
  std::srand(7);
  for (int trial = 0; trial < 300; ++trial) {
    Eigen::Matrix3d s = Eigen::Matrix3d::Random();
    if (trial % 3 == 1) s.col(2) = 1e-3 * s.col(0);  // nearly rank 2 (a flat one-ring)
    if (trial % 3 == 2) s = Eigen::AngleAxisd(0.01 * trial, Eigen::Vector3d::UnitY()).toRotationMatrix();
    const Eigen::JacobiSVD<Eigen::Matrix3d> svd(s, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    d(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant();
    const Eigen::Matrix3d expected = svd.matrixV() * d * svd.matrixU().transpose();
    const Eigen::Matrix3d r = NearestRotation(s);
    EXPECT_LT((r - expected).cwiseAbs().maxCoeff(), 1e-9) << "trial " << trial << "\n" << s;
    EXPECT_NEAR(r.determinant(), 1.0, 1e-12);
    EXPECT_LT((r * r.transpose() - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff(), 1e-12);
  }
  // A pure rotation's covariance S = Σ e (Re)ᵀ = (Σ e eᵀ)·Rᵀ gives back R.
  const Eigen::Matrix3d rot = Eigen::AngleAxisd(2.0, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  const Eigen::Matrix3d spread = Eigen::Vector3d(3, 2, 0).asDiagonal();  // planar edges, like a flat one-ring
  EXPECT_LT((NearestRotation(spread * rot.transpose()) - rot).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_TRUE(NearestRotation(Eigen::Matrix3d::Zero()).isIdentity());
}

TEST(Arap, RestHandlesGiveTheRestShape) {
  const GeneratedMesh bar = Bar();
  const auto model = CotangentModel(bar);
  const DeformationConstraints c = HeldStartDraggedEnd();
  auto solver = ArapSolver::Create(model, c);
  ASSERT_TRUE(solver.ok()) << solver.status().message();
  const ArapRun run = RunArap(*solver, Transformed(bar.positions, c.handles, Eigen::Affine3d::Identity()), {});
  EXPECT_LT((run.positions - bar.positions).cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_EQ(run.report.iterations, 1);
  EXPECT_LT(run.report.energy, 1e-20);
}

// Twisting the bar's free end by 90°: Laplacian editing keeps δ in its rest
// orientation, so the tube collapses toward the twist; ARAP rotates the
// detail and keeps edge lengths.
TEST(Arap, TwistKeepsEdgeLengthsBetterThanLaplacianEditing) {
  const GeneratedMesh bar = Bar();
  const auto model = CotangentModel(bar);
  const DeformationConstraints c = HeldStartDraggedEnd();
  const Eigen::Affine3d twist(Eigen::AngleAxisd(std::numbers::pi / 2, Eigen::Vector3d::UnitX()));
  const Eigen::MatrixX3d targets = Transformed(bar.positions, c.handles, twist);

  const Eigen::MatrixX3d laplacian = RunLaplacian(model, c, targets);
  auto solver = ArapSolver::Create(model, c);
  ASSERT_TRUE(solver.ok()) << solver.status().message();
  ArapOptions options;
  options.max_iterations = 200;
  options.tolerance = 1e-6;
  const ArapRun arap = RunArap(*solver, targets, options);

  // A pure twist keeps every cross-section round: mean |r − 0.5| over the vertices.
  const auto radius_error = [&](const Eigen::MatrixX3d& p) {
    return (p.rightCols<2>().rowwise().norm().array() - 0.5).abs().mean();
  };
  // Edge lengths: a 90° twist must stretch the helical edges (about 3% on
  // average here), the rest is distortion.
  const double laplacian_strain = fixtures::MeanEdgeLengthChange(model->topology, bar.positions, laplacian);
  const double arap_strain = fixtures::MeanEdgeLengthChange(model->topology, bar.positions, arap.positions);
  std::cout << "[ twist    ] mean |Δl|/l: laplacian " << laplacian_strain << ", arap " << arap_strain
            << "; mean |r − 0.5|: laplacian " << radius_error(laplacian) << ", arap " << radius_error(arap.positions)
            << " (" << arap.report.iterations << " ARAP rounds, last change " << arap.report.last_change << ")\n";
  EXPECT_LE(arap.report.last_change, 1e-6);
  EXPECT_LT(arap_strain, 0.7 * laplacian_strain);
  EXPECT_LT(radius_error(arap.positions), 0.3 * radius_error(laplacian));
  for (size_t k = 0; k < c.handles.size(); ++k)
    EXPECT_EQ(arap.positions.row(c.handles[k]), targets.row(static_cast<Eigen::Index>(k)));
  for (uint32_t v : c.fixed) EXPECT_EQ(arap.positions.row(v), bar.positions.row(v));
}

// Moving every handle by one rigid motion: the least-energy shape is the
// whole bar moved rigidly (E = 0), which ARAP finds and Laplacian editing,
// blind to rotation, does not.
TEST(Arap, RigidMotionOfAllHandlesMovesTheBarRigidly) {
  const GeneratedMesh bar = Bar();
  const auto model = CotangentModel(bar);
  DeformationConstraints c;
  c.handles = Ring(0);
  for (uint32_t v : Ring(kRings - 1)) c.handles.push_back(v);
  Eigen::Affine3d motion(Eigen::AngleAxisd(1.0, Eigen::Vector3d(1, 2, 3).normalized()));
  motion.translation() = Eigen::Vector3d(0.5, -1, 2);
  const Eigen::MatrixX3d targets = Transformed(bar.positions, c.handles, motion);
  std::vector<uint32_t> all(static_cast<size_t>(bar.positions.rows()));
  for (uint32_t v = 0; v < all.size(); ++v) all[v] = v;
  const Eigen::MatrixX3d expected = Transformed(bar.positions, all, motion);

  auto solver = ArapSolver::Create(model, c);
  ASSERT_TRUE(solver.ok());
  ArapOptions options;
  options.max_iterations = 1000;
  options.tolerance = 1e-10;
  const ArapRun arap = RunArap(*solver, targets, options);
  const double arap_error = (arap.positions - expected).rowwise().norm().maxCoeff();
  const double laplacian_error = (RunLaplacian(model, c, targets) - expected).rowwise().norm().maxCoeff();
  std::cout << "[ rigid    ] max error: arap " << arap_error << " (" << arap.report.iterations
            << " iterations), laplacian " << laplacian_error << "\n";
  EXPECT_LT(arap_error, 1e-6);
  EXPECT_GT(laplacian_error, 0.1);
  EXPECT_LT(arap.report.energy, 1e-12);
}

TEST(Arap, EnergyNeverIncreasesAndWarmStartResumes) {
  const GeneratedMesh bar = Bar();
  const auto model = CotangentModel(bar);
  const DeformationConstraints c = HeldStartDraggedEnd();
  const Eigen::Affine3d bend =
      Eigen::Translation3d(-1.0, 1.5, 0) * Eigen::AngleAxisd(std::numbers::pi / 3, Eigen::Vector3d::UnitZ());
  const Eigen::MatrixX3d targets = Transformed(bar.positions, c.handles, bend);
  auto solver = ArapSolver::Create(model, c);
  ASSERT_TRUE(solver.ok());
  ArapOptions options;
  options.tolerance = 0;
  double previous = INFINITY;
  for (int k = 1; k <= 6; ++k) {
    options.max_iterations = k;
    const ArapRun run = RunArap(*solver, targets, options);
    EXPECT_EQ(run.report.iterations, k);
    EXPECT_LE(run.report.energy, previous * (1 + 1e-12)) << "round " << k;
    previous = run.report.energy;
  }
  // 3 rounds, then 3 more from there, is the same as 6 rounds in one go.
  options.max_iterations = 3;
  const ArapRun first = RunArap(*solver, targets, options);
  options.warm_start = true;
  const ArapRun resumed = RunArap(*solver, targets, options, Interleave(first.positions));
  options.warm_start = false;
  options.max_iterations = 6;
  const ArapRun straight = RunArap(*solver, targets, options);
  EXPECT_LT((resumed.positions - straight.positions).cwiseAbs().maxCoeff(), 1e-10);
}

TEST(Arap, RegionOfInterestAndSoftHandles) {
  const GeneratedMesh bar = Bar();
  const auto model = CotangentModel(bar);
  DeformationConstraints c;
  c.handles = Ring(kRings - 1);
  for (int r = 25; r < kRings; ++r)
    for (uint32_t v : Ring(r)) c.region_of_interest.push_back(v);
  const Eigen::Affine3d lift(Eigen::Translation3d(0, 0.6, 0));
  const Eigen::MatrixX3d targets = Transformed(bar.positions, c.handles, lift);
  auto solver = ArapSolver::Create(model, c);
  ASSERT_TRUE(solver.ok()) << solver.status().message();
  EXPECT_EQ(solver->unknown_count(), static_cast<size_t>((kRings - 1 - 25) * kSegments));
  const ArapRun run = RunArap(*solver, targets, {});
  for (uint32_t v : Ring(24)) EXPECT_EQ(run.positions.row(v), bar.positions.row(v));
  EXPECT_GT((run.positions.row(Ring(32)[0]) - bar.positions.row(Ring(32)[0])).norm(), 0.05);

  c.mode = ConstraintMode::kSoft;
  c.soft_weight = 10;
  auto soft = ArapSolver::Create(model, c);
  ASSERT_TRUE(soft.ok()) << soft.status().message();
  const ArapRun soft_run = RunArap(*soft, targets, {});
  const double miss = (soft_run.positions.row(c.handles[0]) - targets.row(0)).norm();
  EXPECT_GT(miss, 1e-6);  // pulled toward, not pinned
  EXPECT_LT(miss, 0.1);
}

TEST(Arap, RejectsBadInput) {
  const GeneratedMesh bar = Bar();
  const auto model = CotangentModel(bar);
  DeformationConstraints c;
  c.handles = {0, 9999};
  EXPECT_EQ(ArapSolver::Create(model, c).status().message(),
            "handles[1].index 9999 is out of range (mesh has 656 vertices)");
  c.handles = Ring(0);
  auto solver = ArapSolver::Create(model, c);
  ASSERT_TRUE(solver.ok());
  std::vector<double> positions(3 * 656),
      targets = Interleave(Transformed(bar.positions, c.handles, Eigen::Affine3d::Identity()));
  ArapOptions options;
  options.max_iterations = 0;
  EXPECT_EQ(solver->Solve(targets, options, positions).status().code(), StatusCode::kInvalidArgument);
  options = {};
  options.warm_start = true;
  positions[30] = NAN;
  EXPECT_EQ(solver->Solve(targets, options, positions).status().message(),
            "warm start: positions of vertex 10 are not finite");
  targets.resize(5);
  EXPECT_EQ(solver->Solve(targets, {}, positions).status().code(), StatusCode::kInvalidArgument);
  EXPECT_GT(solver->factorization_bytes(), 0u);
  EXPECT_GE(solver->memory_bytes(), solver->factorization_bytes());
}

}  // namespace
}  // namespace armature
