// Rotations: unit quaternions, matrices, rotation vectors and Euler angles in
// any axis sequence, with exp/log and interpolation along the shortest arc.
// Rotations are never interpolated as Euler angles or matrix elements.
#pragma once

#include <span>
#include <string>

#include <Eigen/Geometry>

namespace armature {

enum class Axis : unsigned char { kX = 0, kY = 1, kZ = 2 };

// Rotation of `angle` radians about a coordinate axis.
Eigen::Quaterniond AxisRotation(Axis axis, double angle);

// Intrinsic composition in the order listed: axes {Z, X, Y} give Rz·Rx·Ry.
// Any length and any sequence (repeats allowed). Angles in radians.
Eigen::Quaterniond EulerToQuaternion(std::span<const Axis> axes, std::span<const double> angles);

// Inverse of EulerToQuaternion for 1 to 3 axes where neighbours differ
// (Tait–Bryan such as ZXY or proper Euler such as ZXZ). With `hint` (the
// previous frame's angles) the solution nearest to it is chosen, unwrapping
// by 2π, so exported curves stay continuous. Returns false for sequences it
// cannot invert (more than 3 axes, or equal neighbours), leaving `angles` with
// a best effort: the first three axes decomposed, the rest zero.
bool QuaternionToEuler(const Eigen::Quaterniond& q, std::span<const Axis> axes, std::span<double> angles,
                       std::span<const double> hint = {});

// exp: rotation vector (axis·angle) → rotation; log: its inverse, with the
// angle in [0, π].
Eigen::Quaterniond ExpQuaternion(const Eigen::Vector3d& rotation_vector);
Eigen::Vector3d LogQuaternion(const Eigen::Quaterniond& q);
Eigen::Matrix3d ExpMatrix(const Eigen::Vector3d& rotation_vector);  // Rodrigues
Eigen::Vector3d LogMatrix(const Eigen::Matrix3d& r);

// Spherical linear interpolation along the shortest arc, constant angular
// speed in t.
Eigen::Quaterniond Slerp(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b, double t);
// three.js's Quaternion.slerpFlat, the flavour its AnimationMixer blends
// with: shortest arc; below a 0.9995 cosine the textbook sin formula (not
// renormalized), above it lerp then normalize; equal inputs return `a`.
// Blending uses it so a browser mixing locally shows the server's pose.
Eigen::Quaterniond SlerpFlat(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b, double t);
// The matrix form R1·exp(t·log(R1ᵀR2)); agrees with Slerp.
Eigen::Matrix3d SlerpMatrix(const Eigen::Matrix3d& r1, const Eigen::Matrix3d& r2, double t);

// Shoemake's squad: a C¹ quaternion spline through q1 → q2 with control
// points from SquadControlPoint(q_prev, q, q_next).
Eigen::Quaterniond SquadControlPoint(const Eigen::Quaterniond& prev, const Eigen::Quaterniond& q,
                                     const Eigen::Quaterniond& next);
Eigen::Quaterniond Squad(const Eigen::Quaterniond& q1, const Eigen::Quaterniond& s1, const Eigen::Quaterniond& s2,
                         const Eigen::Quaterniond& q2, double t);

// Squad control points for keys at uneven times: `dt_prev` and `dt_next` are
// the seconds to the neighbouring keys. The key's angular velocity is the
// derivative of the parabola through the three keys (in the key's tangent
// space), and the incoming `s_in` and outgoing `s_out` control points differ so
// the spline is C¹ in time, not just in the segment parameter. With equal
// spacing both equal SquadControlPoint. A missing neighbour (pass dt ≤ 0) gives
// a one-sided tangent. Either output may be null when not needed.
void SquadControlPoints(const Eigen::Quaterniond& prev, const Eigen::Quaterniond& q, const Eigen::Quaterniond& next,
                        double dt_prev, double dt_next, Eigen::Quaterniond* s_in, Eigen::Quaterniond* s_out);

// Flips `q` to the hemisphere of `reference` (q and −q are the same rotation).
Eigen::Quaterniond SameHemisphere(const Eigen::Quaterniond& q, const Eigen::Quaterniond& reference);

// The rotation R maximizing tr(R·S) (orthogonal Procrustes; never a
// reflection): ARAP's local step, and the rotation of a polar decomposition
// L = R·S when called with Lᵀ.
Eigen::Matrix3d NearestRotation(const Eigen::Matrix3d& covariance);

}  // namespace armature
