#include "armature/engine/kinematics/ik_dls.h"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "armature/engine/kinematics/joint_limits.h"
#include "armature/engine/math/rotation.h"
#include "ik_internal.h"
#include "kinematics/ik_dls_model.h"

namespace armature {
namespace {

using namespace ik_dls;

constexpr double kMaxStep = 1.5;         // largest change of one coordinate per step (radians, chain lengths)
constexpr double kSlow = 1e-3;           // an accepted step lowering the cost by less than this fraction is slow
constexpr int kSlowSteps = 3;            // slow steps in a row that make a stall
constexpr double kInitialDamping = 0.1;  // μ₀ relative to the largest diagonal of JᵀJ
constexpr double kOffBound = 0.2;        // fraction of its range a coordinate starting on a bound moves in
constexpr int kSettleIterations = 30;    // at most, after the targets are reached
constexpr double kSettleStep = 0.3;      // largest coordinate change of one settling move
constexpr int kProgressWindow = 8;       // iterations over which the cost must at least halve

// Solves a x = b in place for symmetric positive definite `a` by Cholesky
// (Eigen's LLT). Small systems (a limb: 1 to 12 unknowns) use the
// fixed-size LLT, which unrolls; larger ones the workspace's dynamic one.
template <int N = 1>
void SolveInPlace(const Eigen::MatrixXd& a, Eigen::VectorXd& x, Eigen::LLT<Eigen::MatrixXd>& dynamic) {
  if constexpr (N > 12) {
    dynamic.compute(a);
    dynamic.solveInPlace(x);
  } else if (a.rows() == N) {
    const Eigen::LLT<Eigen::Matrix<double, N, N>> llt(a.topLeftCorner<N, N>());
    x.head<N>() = llt.solve(x.head<N>());
  } else {
    SolveInPlace<N + 1>(a, x, dynamic);
  }
}

enum class Shake : unsigned char {
  kOffBounds,  // coordinates sitting on a bound jump to the middle of their range
  kNear,       // every coordinate moves randomly by up to `size` (reflected off bounds)
  kAnywhere,   // every joint takes a random rotation within its limit
};

// Restarts after a stall. kOffBounds targets the commonest trap: a straight
// knee or elbow held on its bound, where the gradient points out of range.
// Returns false when there was nothing to move.
bool Perturb(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, Shake shake, double size) {
  auto uniform01 = [&] { return ik_internal::NextUniform(ws.random_state); };
  auto uniform = [&] { return 2.0 * uniform01() - 1.0; };
  auto reflect = [](double x, double lo, double hi) {
    if (x > hi) x = hi - (x - hi);
    if (x < lo) x = lo + (lo - x);
    return std::clamp(x, lo, hi);
  };
  bool moved = false;
  for (DlsJoint& d : ws.dls_joints) {
    Trs& local = ws.local[d.joint];
    switch (d.param) {
      case Param::kEuler:
      case Param::kHinge:
        for (int c = 0; c < d.columns; ++c) {
          const bool bounded = std::isfinite(d.lower[c]) && std::isfinite(d.upper[c]);
          double& x = d.coords[c];
          if (shake == Shake::kOffBounds) {
            if (bounded && (x <= d.lower[c] + kAtBound || x >= d.upper[c] - kAtBound))
              x = 0.5 * (d.lower[c] + d.upper[c]), moved = true;
          } else if (shake == Shake::kAnywhere && bounded) {
            x = d.lower[c] + uniform01() * (d.upper[c] - d.lower[c]), moved = true;
          } else {
            x = reflect(x + (shake == Shake::kAnywhere ? std::numbers::pi : size) * uniform(), d.lower[c], d.upper[c]);
            moved = true;
          }
        }
        SetRotationFromCoords(skeleton, request, ws, d);
        break;
      case Param::kTranslation: {
        if (shake == Shake::kOffBounds) break;
        const Eigen::Vector3d move(uniform(), uniform(), uniform());
        d.coords += 0.25 * size * move;
        local.translation += ik_internal::WorldMoveToLocal(skeleton, ws, d.joint, 0.25 * size * ws.chain_length * move);
        moved = true;
        break;
      }
      case Param::kRotationVector: {
        const Eigen::Quaterniond& rest = skeleton.rest[d.joint].rotation;
        if (shake == Shake::kOffBounds) {
          if (d.limit < 0) break;
          const JointLimit& l = request.limits[d.limit];
          const SwingTwist st = DecomposeSwingTwist(rest.conjugate() * local.rotation, l.axis.normalized());
          if (st.swing_angle < l.cone_deg * kDegToRad - kAtBound) break;
          local.rotation = rest * ExpQuaternion(0.5 * LogQuaternion(st.swing)) * st.twist;
          moved = true;
          break;
        }
        const Eigen::Vector3d u(uniform01(), uniform01(), uniform01());
        if (shake == Shake::kAnywhere && d.limit >= 0) {
          local.rotation = rest * SampleWithinLimit(request.limits[d.limit], u);
        } else {
          const double reach = shake == Shake::kAnywhere ? std::numbers::pi : size;
          const Eigen::Vector3d v = reach * (2.0 * u - Eigen::Vector3d::Ones());
          local.rotation = ik_internal::Limited(skeleton, request, ws, d.joint, ExpQuaternion(v) * local.rotation);
        }
        moved = true;
        break;
      }
    }
  }
  ik_internal::UpdateWorld(skeleton, ws, ws.update);
  return moved;
}

// Minimum-norm step δ = −α·d + Jᵀ(JJᵀ + εI)⁻¹(r + α·J·d): zero linearized
// residual, as near as possible to moving the fraction α of the way back
// to the start (d = q − q_start; α = 0: a plain Gauss–Newton correction).
// Coordinates on a bound stay put.
void ProjectedStep(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, double alpha) {
  BuildJacobian(skeleton, request, ws);
  if (alpha > 0)
    StartOffsets(skeleton, ws);
  else
    ws.regularization.setZero();
  ForEachCoordinateOnBound(ws, [&](int col, int) {
    ws.jacobian.col(col).setZero();
    ws.regularization[col] = 0.0;
  });
  ws.gram.noalias() = ws.jacobian.lazyProduct(ws.jacobian.transpose());
  ws.gram.diagonal().array() += 1e-9 * (1.0 + ws.gram.diagonal().maxCoeff());
  ws.task_correction.noalias() = ws.residual + alpha * (ws.jacobian * ws.regularization);
  SolveInPlace(ws.gram, ws.task_correction, ws.gram_llt);
  ws.step.noalias() = ws.jacobian.transpose() * ws.task_correction;
  ws.step -= alpha * ws.regularization;
}

// After the targets are reached, slides along the solutions towards the
// start pose (Gauss–Newton on min ½‖q − q_start‖² subject to the targets):
// a projected step, then corrections back onto the targets; a move is kept
// when the targets stay reached and the pose gets nearer the start, else
// retried at half the size. Returns the iterations used.
int Settle(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, int budget) {
  const double alpha = std::min(1.0, request.options.regularization);
  budget = std::min(budget, kSettleIterations);
  double distance = DistanceFromStart(ws);
  double scale = 1.0;
  int used = 0;
  while (used < budget && scale > 1.0 / 16 && !ik_internal::CheckInterrupt(request)) {
    ProjectedStep(skeleton, request, ws, alpha);
    const double largest = ws.step.cwiseAbs().maxCoeff();
    if (largest < 1e-9) break;
    ws.step *= scale * std::min(1.0, kSettleStep / largest);
    Store(ws, &DlsJoint::saved);
    ApplyStep(skeleton, request, ws);
    ++used;
    bool reached = Evaluate(request, ws).reached;
    for (int k = 0; k < 3 && !reached && used < budget; ++k, ++used) {
      ProjectedStep(skeleton, request, ws, 0.0);
      ApplyStep(skeleton, request, ws);
      reached = Evaluate(request, ws).reached;
    }
    const double nearer = DistanceFromStart(ws);
    if (reached && nearer < distance) {
      if (distance - nearer < 1e-8 * (1.0 + distance)) break;  // settled
      distance = nearer;
      scale = std::min(1.0, 2.0 * scale);
    } else {
      Restore(skeleton, request, ws, &DlsJoint::saved);
      Evaluate(request, ws);
      scale *= 0.5;
    }
  }
  return used;
}

// A coordinate starting on a bound (a straight knee at 0°) sits on a saddle
// of the reach problem whose gradient points out of range: start from a
// little inside instead (the regularization still refers to the given start).
void StartInsideBounds(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws) {
  for (DlsJoint& d : ws.dls_joints) {
    if (d.param != Param::kHinge && d.param != Param::kEuler) continue;
    bool moved = false;
    for (int c = 0; c < d.columns; ++c) {
      if (!std::isfinite(d.lower[c]) || !std::isfinite(d.upper[c])) continue;
      const double inwards = kOffBound * (d.upper[c] - d.lower[c]);
      if (d.coords[c] <= d.lower[c] + kAtBound) d.coords[c] += inwards, moved = true;
      if (d.coords[c] >= d.upper[c] - kAtBound) d.coords[c] -= inwards, moved = true;
    }
    if (moved) SetRotationFromCoords(skeleton, request, ws, d);
  }
  ik_internal::UpdateWorld(skeleton, ws, ws.update);
}

// The Levenberg–Marquardt iteration's state between steps.
struct DlsProgress {
  Cost cost;
  double best_task = INFINITY;
  double mu = -1, nu = 2;  // damping, and Nielsen's factor for the next rejection
  double checkpoint = 0;   // the cost at the start of the progress window
  int iterations = 0, restarts = 0, since_checkpoint = 0, slow = 0;
  bool linearized = false;
};

// One damped step, kept when it lowers the cost (μ then shrinks) or undone
// (μ grows). Returns whether the solve has stalled.
bool DampedStep(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, DlsProgress& p) {
  ws.damped = ws.hessian;
  ws.damped.diagonal().array() += p.mu;
  ws.step = ws.gradient;
  SolveInPlace(ws.damped, ws.step, ws.llt);
  const double largest = ws.step.cwiseAbs().maxCoeff();
  if (largest > kMaxStep) ws.step *= kMaxStep / largest;
  Store(ws, &DlsJoint::saved);
  ApplyStep(skeleton, request, ws);
  ++p.iterations;
  ws.product.noalias() = ws.hessian * ws.step;
  const double predicted = ws.step.dot(ws.gradient) - 0.5 * ws.step.dot(ws.product);
  const Cost next = Evaluate(request, ws);
  bool stalled = false;
  if (next.task < p.cost.task && predicted > 0) {
    const double rho = (p.cost.task - next.task) / predicted;
    const double t = 2.0 * rho - 1.0;
    p.mu *= std::max(1.0 / 3.0, 1.0 - t * t * t);
    p.nu = 2;
    p.slow = p.cost.task - next.task < kSlow * p.cost.task ? p.slow + 1 : 0;
    stalled = p.slow >= kSlowSteps;
    p.cost = next;
    p.linearized = false;
  } else {
    Restore(skeleton, request, ws, &DlsJoint::saved);
    p.mu *= p.nu;
    p.nu *= 2;
    stalled = p.mu > 1e10 || largest < 1e-12;
  }
  if (++p.since_checkpoint == kProgressWindow) {
    stalled = stalled || p.cost.task > 0.5 * p.checkpoint;
    p.checkpoint = p.cost.task;
    p.since_checkpoint = 0;
  }
  return stalled;
}

// A local minimum or a saddle (a straight limb): restart from the best pose
// so far, shaken harder each time. False when the restarts are used up.
bool Restart(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, DlsProgress& p) {
  if (p.cost.task < p.best_task) p.best_task = p.cost.task, Store(ws, &DlsJoint::best);
  if (p.restarts >= request.options.max_restarts) return false;
  // First off the bounds, then near the best pose, then anywhere.
  Restore(skeleton, request, ws, &DlsJoint::best);
  if (p.restarts > 0 || !Perturb(skeleton, request, ws, Shake::kOffBounds, 0))
    Perturb(skeleton, request, ws, p.restarts >= 2 ? Shake::kAnywhere : Shake::kNear, 0.3 * (p.restarts + 1));
  ++p.restarts;
  p.slow = 0;
  p.cost = Evaluate(request, ws);
  p.checkpoint = p.cost.task;
  p.since_checkpoint = 0;
  p.mu = -1;
  p.nu = 2;
  p.linearized = false;
  return true;
}

}  // namespace

void SolveDls(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, IkResult& result) {
  Setup(skeleton, request, ws);
  const IkOptions& o = request.options;
  DlsProgress p;
  p.cost = Evaluate(request, ws);
  if (!p.cost.reached) {
    StartInsideBounds(skeleton, request, ws);
    p.cost = Evaluate(request, ws);
  }
  p.checkpoint = p.cost.task;
  IkStop stop = IkStop::kIterationCap;
  while (!p.cost.reached) {
    if (p.iterations >= o.max_iterations) break;
    if (const std::optional<IkStop> interrupt = ik_internal::CheckInterrupt(request)) {
      stop = *interrupt;
      break;
    }
    if (!p.linearized) {
      Linearize(skeleton, request, ws);
      p.linearized = true;
      if (p.mu < 0) p.mu = kInitialDamping * std::max(ws.hessian.diagonal().maxCoeff(), 1e-9);
      // Linearizing costs rows × columns²: look at the clock again before the
      // solve (should_stop stays once per iteration, as documented).
      if (request.deadline && std::chrono::steady_clock::now() >= *request.deadline) {
        stop = IkStop::kDeadline;
        break;
      }
    }
    const bool stalled = DampedStep(skeleton, request, ws, p);
    if (stalled && !p.cost.reached && !Restart(skeleton, request, ws, p)) {
      stop = IkStop::kStalled;
      break;
    }
  }
  if (!p.cost.reached && p.best_task < p.cost.task) Restore(skeleton, request, ws, &DlsJoint::best);
  if (p.cost.reached && o.regularization > 0 && stop != IkStop::kDeadline && stop != IkStop::kCancelled)
    p.iterations += Settle(skeleton, request, ws, o.max_iterations - p.iterations);
  ik_internal::FinishResult(request, ws, p.iterations, stop, result);
  result.restarts = p.restarts;
}

}  // namespace armature
