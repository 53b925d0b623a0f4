// The damped least-squares solver's model (ik_dls.cc runs the iteration):
// its coordinates per free joint and their bounds, the weighted residual, the
// Jacobian and normal equations, and steps applied or undone. Private to the
// engine.
#pragma once

#include <numbers>

#include "armature/engine/kinematics/ik_types.h"
#include "armature/engine/kinematics/ik_workspace.h"
#include "armature/engine/anim/skeleton.h"

namespace armature::ik_dls {

using DlsJoint = IkWorkspace::DlsJoint;
using Param = DlsJoint::Param;

constexpr double kDegToRad = std::numbers::pi / 180.0;
constexpr double kAtBound = 1e-7;  // radians: a coordinate this close to a bound is on it

// The joint's local rotation from its Euler or hinge coordinates; for Euler
// joints the three axis rotations are kept for the Jacobian's axes.
void SetRotationFromCoords(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, DlsJoint& d);

// One entry per free joint (start pose projected onto its limit) and per
// translated root; per-effector lists of the entries that move it.
void Setup(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws);

struct Cost {
  double task = 0;  // ½‖weighted residual‖²
  bool reached = false;
};

// Fills ws.residual (weighted, positions in chain lengths) and the cost.
Cost Evaluate(const IkRequest& request, IkWorkspace& ws);

// Squared distance of the pose from the start pose, in the coordinates.
double DistanceFromStart(const IkWorkspace& ws);

// Columns' world axes and the Jacobian.
void BuildJacobian(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws);

// ws.regularization = q − q_start in the columns' coordinates.
void StartOffsets(const Skeleton& skeleton, IkWorkspace& ws);

// The Jacobian and the normal equations H = JᵀJ, g = Jᵀr, with coordinates
// on a bound that the descent direction pushes against frozen.
void Linearize(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws);

// A copy of the free joints' state (DlsJoint::saved or ::best), and back.
void Store(IkWorkspace& ws, DlsJoint::Snapshot DlsJoint::*slot);
void Restore(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws, DlsJoint::Snapshot DlsJoint::*slot);

// Moves every coordinate by ws.step (clamped to bounds; ws.step then holds
// the change actually made) and updates forward kinematics.
void ApplyStep(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& ws);

// Calls `on_bound(column, outward_sign)` for each coordinate sitting on a
// bound: +1 when increasing it would leave the range, −1 when decreasing.
template <class OnBound>
void ForEachCoordinateOnBound(const IkWorkspace& ws, OnBound&& on_bound) {
  for (const DlsJoint& d : ws.dls_joints) {
    if (d.param == Param::kEuler || d.param == Param::kHinge) {
      for (int c = 0; c < d.columns; ++c) {
        if (d.coords[c] >= d.upper[c] - kAtBound) on_bound(d.first_column + c, 1);
        if (d.coords[c] <= d.lower[c] + kAtBound) on_bound(d.first_column + c, -1);
      }
    } else if (d.param == Param::kRotationVector) {
      if (d.swing_at_bound) on_bound(d.first_column, 1);
      if (d.twist_at_bound != 0) on_bound(d.first_column + 1, d.twist_at_bound);
    }
  }
}

}  // namespace armature::ik_dls
