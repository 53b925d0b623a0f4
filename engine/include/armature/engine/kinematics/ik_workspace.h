// Per-request IK state (Pinocchio's Data): the request resolved against the
// skeleton (indices instead of names), the pose being solved and the
// solvers' scratch. Keep one per thread and reuse it: buffers keep their
// capacity, and nothing is allocated inside the solvers' iteration loops.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "armature/engine/kinematics/ik_types.h"
#include "armature/engine/anim/skeleton.h"
#include "armature/base/status.h"

namespace armature {

struct IkWorkspace {
  struct Effector {
    int joint = -1;
    Eigen::Vector3d offset = Eigen::Vector3d::Zero();
    bool has_position = false;
    bool has_rotation = false;
    Eigen::Vector3d target_position = Eigen::Vector3d::Zero();
    Eigen::Quaterniond target_rotation = Eigen::Quaterniond::Identity();
    double position_weight = 1.0;
    double rotation_weight = 1.0;
    // [path_begin, path_end) in `paths`: the free joints that move this
    // effector (its free ancestors, itself included), effector side first.
    int path_begin = 0;
    int path_end = 0;
    int translated_root = -1;  // the root whose translation moves it, or -1
    int body_root = -1;        // the joint carrying the body above it (BodyRootAbove)
  };
  std::vector<Effector> effectors;
  std::vector<int> name_hints;  // joint indices found by the previous request's name lookups
  size_t name_lookups = 0;
  std::vector<int> paths;
  std::vector<int> limit_of;          // per joint: index into request.limits, or -1
  std::vector<int> free_joints;       // ascending
  std::vector<int> translated_roots;  // ascending
  std::vector<int> update;            // joints whose world transform follows the free ones, ascending
  std::vector<unsigned char> mark;    // per joint scratch
  double chain_length = 1.0;          // longest free path to an effector point (world units)
  double position_tolerance = 0.0;    // resolved (world units)

  // The pose being solved and its world transforms (only joints that lead
  // to an effector are kept current).
  std::vector<Trs> local;
  std::vector<Eigen::Matrix3d> world_linear;  // rotation · scale, maps child offsets
  std::vector<Eigen::Quaterniond> world_rotation;
  std::vector<Eigen::Vector3d> world_position;

  // DLS: one entry per free joint (and per translated root).
  struct DlsJoint {
    enum class Param : unsigned char { kRotationVector, kHinge, kEuler, kTranslation };
    int joint = -1;
    int limit = -1;
    Param param = Param::kRotationVector;
    int first_column = 0;
    int columns = 3;
    Eigen::Vector3d coords = Eigen::Vector3d::Zero();  // Euler angles, hinge angle, translation / chain length
    Eigen::Vector3d start_coords = Eigen::Vector3d::Zero();
    Eigen::Vector3d lower = Eigen::Vector3d::Zero();
    Eigen::Vector3d upper = Eigen::Vector3d::Zero();
    Eigen::Quaterniond start_rotation = Eigen::Quaterniond::Identity();
    Eigen::Matrix3d axes = Eigen::Matrix3d::Identity();    // world axes of the columns this iteration
    Eigen::Vector3d unit_axis = Eigen::Vector3d::UnitX();  // hinge or twist axis, in the rest frame
    Eigen::Quaterniond parts[3] = {Eigen::Quaterniond::Identity(), Eigen::Quaterniond::Identity(),
                                   Eigen::Quaterniond::Identity()};  // Euler: the rotation about each axis
    struct Snapshot {
      Trs local;
      Eigen::Vector3d coords = Eigen::Vector3d::Zero();
    };
    Snapshot saved;               // before a trial step
    Snapshot best;                // the best pose before a restart
    bool swing_at_bound = false;  // cone joints: the active set's swing direction is axes.col(0)
    int twist_at_bound = 0;       // −1 lower, +1 upper; its direction is axes.col(1)
  };
  std::vector<DlsJoint> dls_joints;
  std::vector<int> dls_paths;  // per effector [path_begin, path_end): indices into dls_joints
  std::vector<int> dls_path_begin, dls_path_end;
  Eigen::MatrixXd jacobian;
  Eigen::MatrixXd hessian;
  Eigen::MatrixXd damped;
  Eigen::VectorXd residual;
  Eigen::VectorXd gradient;
  Eigen::VectorXd step;
  Eigen::VectorXd regularization;
  Eigen::VectorXd product;
  Eigen::LLT<Eigen::MatrixXd> llt;
  Eigen::MatrixXd gram;  // JJᵀ, for settling towards the start pose
  Eigen::LLT<Eigen::MatrixXd> gram_llt;
  Eigen::VectorXd task_correction;

  // FABRIK: points along the chain and the distances between them.
  std::vector<Eigen::Vector3d> points;
  std::vector<double> lengths;

  uint64_t random_state = 0;
};

// Checks `request` against `skeleton` (a valid skeleton) and fills
// `workspace`: INVALID_ARGUMENT naming the offending field otherwise.
Status PrepareIkWorkspace(const Skeleton& skeleton, const IkRequest& request, IkWorkspace& workspace);

}  // namespace armature
