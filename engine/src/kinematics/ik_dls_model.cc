#include "kinematics/ik_dls_model.h"

#include <algorithm>
#include <cmath>

#include "armature/engine/kinematics/joint_limits.h"
#include "armature/engine/math/rotation.h"
#include "ik_internal.h"

namespace armature::ik_dls {
namespace {

using ik_internal::ParentWorldRotation;

// An axis whose range covers a full turn is unbounded, so it can wrap.
void SetBounds(double lo_deg, double hi_deg, double& lo, double& hi) {
  const bool full = hi_deg - lo_deg >= 360.0;
  lo = full ? -INFINITY : lo_deg * kDegToRad;
  hi = full ? INFINITY : hi_deg * kDegToRad;
}

bool IsHinge(const JointLimit& l) { return l.kind == JointLimit::Kind::kSwingTwist && l.cone_deg == 0; }

// Squared distance of one entry from the start pose, in its coordinates.
double RegularizationSquared(const IkWorkspace& ws, const DlsJoint& d) {
  switch (d.param) {
    case Param::kRotationVector:
      return LogQuaternion(ws.local[d.joint].rotation * d.start_rotation.conjugate()).squaredNorm();
    case Param::kHinge: return (d.coords[0] - d.start_coords[0]) * (d.coords[0] - d.start_coords[0]);
    default: return (d.coords - d.start_coords).squaredNorm();
  }
}

// World axes of a cone joint's columns: identity inside the cone; on its
// edge (swing or twist at a bound) [swing-increasing, twist-increasing, ⊥].
void ConeAxes(const Skeleton& skeleton, const IkRequest& request, const IkWorkspace& ws, DlsJoint& d) {
  d.swing_at_bound = false;
  d.twist_at_bound = 0;
  d.axes.setIdentity();
  if (d.limit < 0) return;
  const JointLimit& l = request.limits[d.limit];
  const Eigen::Vector3d& a = d.unit_axis;
  const Eigen::Quaterniond& rest = skeleton.rest[d.joint].rotation;
  const Eigen::Quaterniond delta = rest.conjugate() * ws.local[d.joint].rotation;
  // cos(swing/2) = |(w, v·a)|, twist = 2·atan2(v·a, w): no full decomposition.
  const double along = delta.vec().dot(a);
  d.swing_at_bound =
      l.cone_deg < 180 && std::hypot(delta.w(), along) <= std::cos(0.5 * (l.cone_deg * kDegToRad - kAtBound));
  double lo, hi;
  SetBounds(l.twist_min_deg, l.twist_max_deg, lo, hi);
  if (std::isfinite(hi)) {
    const double twist = 2.0 * std::atan2(delta.w() < 0 ? -along : along, std::abs(delta.w()));
    const double t = ClampAngle(twist, lo - 1.0, hi + 1.0);
    d.twist_at_bound = t >= hi - kAtBound ? 1 : (t <= lo + kAtBound ? -1 : 0);
  }
  if (!d.swing_at_bound && d.twist_at_bound == 0) return;
  const Eigen::Vector3d bone = delta * a;
  Eigen::Vector3d n = a.cross(bone);
  if (n.norm() < 1e-9) n = bone.cross(std::abs(bone.x()) < 0.9 ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY());
  const Eigen::Quaterniond frame = ParentWorldRotation(skeleton, ws, d.joint) * rest;
  d.axes.col(0) = frame * n.normalized();
  d.axes.col(1) = frame * bone;
  d.axes.col(2) = d.axes.col(0).cross(d.axes.col(1));
}

}  // namespace

// The joint's local rotation from its Euler or hinge coordinates; for Euler
// joints the three axis rotations are kept for the Jacobian's axes.
void SetRotationFromCoords(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, DlsJoint& d) {
  const Eigen::Quaterniond& rest = skeleton.rest[d.joint].rotation;
  if (d.param == Param::kEuler) {
    const JointLimit& l = request.limits[d.limit];
    Eigen::Quaterniond q = rest;
    for (int i = 0; i < 3; ++i) {
      const double half = 0.5 * d.coords[i];
      d.parts[i] = Eigen::Quaterniond(std::cos(half), 0, 0, 0);
      d.parts[i].vec()[static_cast<int>(l.order[i])] = std::sin(half);
      q = q * d.parts[i];
    }
    ws.local[d.joint].rotation = q;  // unit: built from unit factors, afresh each time
  } else {
    const double half = 0.5 * d.coords[0];
    const Eigen::Quaterniond hinge(std::cos(half), std::sin(half) * d.unit_axis.x(), std::sin(half) * d.unit_axis.y(),
                                   std::sin(half) * d.unit_axis.z());
    ws.local[d.joint].rotation = rest * hinge;
  }
}

// One entry per free joint (start pose projected onto its limit) and per
// translated root; per-effector lists of the entries that move it.
void Setup(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws) {
  ws.dls_joints.clear();
  int columns = 0;
  for (int j : ws.free_joints) {
    DlsJoint d;
    d.joint = j;
    d.limit = ws.limit_of[j];
    Trs& local = ws.local[j];
    const Eigen::Quaterniond delta = skeleton.rest[j].rotation.conjugate() * local.rotation;
    if (d.limit >= 0 && request.limits[d.limit].kind == JointLimit::Kind::kEuler) {
      const JointLimit& l = request.limits[d.limit];
      d.param = Param::kEuler;
      d.coords = ClampedEulerAngles(l, delta);
      for (int i = 0; i < 3; ++i) SetBounds(l.min_deg[i], l.max_deg[i], d.lower[i], d.upper[i]);
      SetRotationFromCoords(skeleton, request, ws, d);
    } else if (d.limit >= 0 && IsHinge(request.limits[d.limit])) {
      const JointLimit& l = request.limits[d.limit];
      d.param = Param::kHinge;
      d.columns = 1;
      SetBounds(l.twist_min_deg, l.twist_max_deg, d.lower[0], d.upper[0]);
      d.unit_axis = l.axis.normalized();
      const double twist = DecomposeSwingTwist(delta, d.unit_axis).twist_angle;
      d.coords[0] = std::isfinite(d.lower[0]) ? ClampAngle(twist, d.lower[0], d.upper[0]) : twist;
      SetRotationFromCoords(skeleton, request, ws, d);
    } else {
      d.param = Param::kRotationVector;
      if (d.limit >= 0) d.unit_axis = request.limits[d.limit].axis.normalized();
      local.rotation = ik_internal::Limited(skeleton, request, ws, j, local.rotation);
    }
    d.start_rotation = local.rotation;
    d.start_coords = d.coords;
    d.first_column = columns;
    columns += d.columns;
    ws.dls_joints.push_back(d);
  }
  for (int r : ws.translated_roots) {
    DlsJoint d;
    d.joint = r;
    d.param = Param::kTranslation;
    d.lower.setConstant(-INFINITY);
    d.upper.setConstant(INFINITY);
    d.first_column = columns;
    columns += 3;
    ws.dls_joints.push_back(d);
  }
  ik_internal::UpdateWorld(skeleton, ws, ws.update);

  const int free_count = static_cast<int>(ws.free_joints.size());
  ws.dls_paths.clear();
  ws.dls_path_begin.resize(ws.effectors.size());
  ws.dls_path_end.resize(ws.effectors.size());
  int rows = 0;
  for (size_t i = 0; i < ws.effectors.size(); ++i) {
    const IkWorkspace::Effector& e = ws.effectors[i];
    ws.dls_path_begin[i] = static_cast<int>(ws.dls_paths.size());
    for (int k = e.path_begin; k < e.path_end; ++k)
      ws.dls_paths.push_back(static_cast<int>(
          std::lower_bound(ws.free_joints.begin(), ws.free_joints.end(), ws.paths[k]) - ws.free_joints.begin()));
    if (e.translated_root >= 0)
      ws.dls_paths.push_back(
          free_count +
          static_cast<int>(std::lower_bound(ws.translated_roots.begin(), ws.translated_roots.end(), e.translated_root) -
                           ws.translated_roots.begin()));
    ws.dls_path_end[i] = static_cast<int>(ws.dls_paths.size());
    rows += (e.has_position ? 3 : 0) + (e.has_rotation ? 3 : 0);
  }
  if (ws.damped.rows() != columns) ws.llt = Eigen::LLT<Eigen::MatrixXd>(columns);
  if (ws.gram.rows() != rows) ws.gram_llt = Eigen::LLT<Eigen::MatrixXd>(rows);
  ws.gram.resize(rows, rows);
  ws.task_correction.resize(rows);
  ws.jacobian.resize(rows, columns);
  ws.residual.resize(rows);
  ws.hessian.resize(columns, columns);
  ws.damped.resize(columns, columns);
  ws.gradient.resize(columns);
  ws.step.resize(columns);
  ws.regularization.resize(columns);
  ws.product.resize(columns);
}

// Fills ws.residual (weighted, positions in chain lengths) and the cost.
Cost Evaluate(const IkRequest& request, IkWorkspace& ws) {
  Cost cost;
  cost.reached = true;
  int row = 0;
  for (const IkWorkspace::Effector& e : ws.effectors) {
    if (e.has_position) {
      const Eigen::Vector3d d = e.target_position - ik_internal::EffectorPoint(ws, e);
      cost.reached = cost.reached && d.norm() <= ws.position_tolerance;
      ws.residual.segment<3>(row) = (std::sqrt(e.position_weight) / ws.chain_length) * d;
      row += 3;
    }
    if (e.has_rotation) {
      const Eigen::Vector3d v = ik_internal::RotationResidual(ws, e);
      cost.reached = cost.reached && v.norm() <= request.options.rotation_tolerance;
      ws.residual.segment<3>(row) = std::sqrt(e.rotation_weight) * v;
      row += 3;
    }
  }
  cost.task = 0.5 * ws.residual.squaredNorm();
  return cost;
}

double DistanceFromStart(const IkWorkspace& ws) {
  double sum = 0;
  for (const DlsJoint& d : ws.dls_joints) sum += RegularizationSquared(ws, d);
  return sum;
}

// Columns' world axes and the Jacobian.
void BuildJacobian(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws) {
  for (DlsJoint& d : ws.dls_joints) {
    const Eigen::Quaterniond parent = ParentWorldRotation(skeleton, ws, d.joint);
    switch (d.param) {
      case Param::kTranslation: d.axes.setIdentity(); break;
      case Param::kHinge: d.axes.col(0) = parent * (skeleton.rest[d.joint].rotation * d.unit_axis); break;
      case Param::kEuler: {
        const JointLimit& l = request.limits[d.limit];
        Eigen::Quaterniond frame = parent * skeleton.rest[d.joint].rotation;
        for (int i = 0; i < 3; ++i) {
          d.axes.col(i) = frame * Eigen::Vector3d::Unit(static_cast<int>(l.order[i]));
          frame = frame * d.parts[i];
        }
        break;
      }
      case Param::kRotationVector: ConeAxes(skeleton, request, ws, d); break;
    }
  }
  ws.jacobian.setZero();
  int row = 0;
  for (size_t i = 0; i < ws.effectors.size(); ++i) {
    const IkWorkspace::Effector& e = ws.effectors[i];
    const Eigen::Vector3d point = ik_internal::EffectorPoint(ws, e);
    const double wp = std::sqrt(e.position_weight), wr = std::sqrt(e.rotation_weight);
    const int rot_row = row + (e.has_position ? 3 : 0);
    for (int k = ws.dls_path_begin[i]; k < ws.dls_path_end[i]; ++k) {
      const DlsJoint& d = ws.dls_joints[ws.dls_paths[k]];
      const Eigen::Vector3d lever = point - ws.world_position[d.joint];
      for (int c = 0; c < d.columns; ++c) {
        const Eigen::Vector3d w = d.axes.col(c);
        if (d.param == Param::kTranslation) {
          if (e.has_position) ws.jacobian.block<3, 1>(row, d.first_column + c) = wp * w;
          continue;
        }
        if (e.has_position) ws.jacobian.block<3, 1>(row, d.first_column + c) = (wp / ws.chain_length) * w.cross(lever);
        if (e.has_rotation) ws.jacobian.block<3, 1>(rot_row, d.first_column + c) = wr * w;
      }
    }
    row = rot_row + (e.has_rotation ? 3 : 0);
  }
}

// ws.regularization = q − q_start in the columns' coordinates.
void StartOffsets(const Skeleton& skeleton, IkWorkspace& ws) {
  for (const DlsJoint& d : ws.dls_joints) {
    if (d.param == Param::kRotationVector) {
      const Eigen::Vector3d v = ParentWorldRotation(skeleton, ws, d.joint) *
                                LogQuaternion(ws.local[d.joint].rotation * d.start_rotation.conjugate());
      ws.regularization.segment<3>(d.first_column).noalias() = d.axes.transpose() * v;
    } else {
      ws.regularization.segment(d.first_column, d.columns) = (d.coords - d.start_coords).head(d.columns);
    }
  }
}

// The Jacobian and the normal equations H = JᵀJ, g = Jᵀr, with coordinates
// on a bound that the descent direction pushes against frozen.
void Linearize(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws) {
  BuildJacobian(skeleton, request, ws);
  ws.hessian.noalias() = ws.jacobian.transpose().lazyProduct(ws.jacobian);  // small: no GEMM blocking
  ws.gradient.noalias() = ws.jacobian.transpose() * ws.residual;
  ForEachCoordinateOnBound(ws, [&](int col, int outward) {
    if (outward * ws.gradient[col] <= 0) return;
    ws.hessian.row(col).setZero();
    ws.hessian.col(col).setZero();
    ws.hessian(col, col) = 1.0;
    ws.gradient[col] = 0.0;
  });
}

// A copy of the free joints' state (DlsJoint::saved or ::best), and back.
void Store(IkWorkspace& ws, DlsJoint::Snapshot DlsJoint::*slot) {
  for (DlsJoint& d : ws.dls_joints) (d.*slot).local = ws.local[d.joint], (d.*slot).coords = d.coords;
}

void Restore(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, DlsJoint::Snapshot DlsJoint::*slot) {
  for (DlsJoint& d : ws.dls_joints) {
    ws.local[d.joint] = (d.*slot).local, d.coords = (d.*slot).coords;
    if (d.param == Param::kEuler) SetRotationFromCoords(skeleton, request, ws, d);
  }
  ik_internal::UpdateWorld(skeleton, ws, ws.update);
}

// Moves every coordinate by ws.step (clamped to bounds; ws.step then holds
// the change actually made) and updates forward kinematics.
void ApplyStep(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws) {
  for (DlsJoint& d : ws.dls_joints) {
    Trs& local = ws.local[d.joint];
    switch (d.param) {
      case Param::kEuler:
      case Param::kHinge:
        for (int c = 0; c < d.columns; ++c) {
          const double before = d.coords[c];
          d.coords[c] = std::clamp(before + ws.step[d.first_column + c], d.lower[c], d.upper[c]);
          ws.step[d.first_column + c] = d.coords[c] - before;
        }
        SetRotationFromCoords(skeleton, request, ws, d);
        break;
      case Param::kTranslation:
        d.coords += ws.step.segment<3>(d.first_column);
        local.translation +=
            ik_internal::WorldMoveToLocal(skeleton, ws, d.joint, ws.chain_length * ws.step.segment<3>(d.first_column));
        break;
      case Param::kRotationVector: {
        const Eigen::Vector3d w = d.axes * ws.step.segment<3>(d.first_column);
        const Eigen::Vector3d v = ParentWorldRotation(skeleton, ws, d.joint).conjugate() * w;
        local.rotation = ik_internal::Limited(skeleton, request, ws, d.joint, ExpQuaternion(v) * local.rotation);
        break;
      }
    }
  }
  ik_internal::UpdateWorld(skeleton, ws, ws.update);
}

}  // namespace armature::ik_dls
