// Armature's DLS against Orocos KDL's ChainIkSolverPos_LMA on the same
// chains and the same reachable targets, both from the rest pose.
//
// The KDL chain mirrors the rig: a fixed segment per bone offset, three
// revolute joints (in the limit's Euler order) per ball joint, one per hinge.
// KDL's LMA does not take joint limits, so it solves an easier problem
// (kdl_valid_% counts the targets it reached within them anyway);
// Armature keeps every joint inside its limit. Both stop at half the
// success threshold (KDL on its weighted error norm, rotation weighted by the
// chain length so a radian counts as one chain length) and are judged alike:
// position within 1e-3 × chain length, rotation within 1e-3 rad.
#include <cmath>
#include <numbers>

#include <kdl/chain.hpp>
#include <kdl/chainfksolverpos_recursive.hpp>
#include <kdl/chainiksolverpos_lma.hpp>

#include "ik_bench_util.h"

namespace armature {
namespace {

using ik_rigs::LimbCase;

KDL::Vector ToKdl(const Eigen::Vector3d& v) { return KDL::Vector(v.x(), v.y(), v.z()); }

KDL::Frame ToKdl(const Eigen::Quaterniond& q, const Eigen::Vector3d& p) {
  return KDL::Frame(KDL::Rotation::Quaternion(q.x(), q.y(), q.z(), q.w()), ToKdl(p));
}

KDL::Joint::JointType RotationAbout(Axis a) {
  return a == Axis::kX ? KDL::Joint::RotX : (a == Axis::kY ? KDL::Joint::RotY : KDL::Joint::RotZ);
}

// From c.root (excluded) down to the effector point.
KDL::Chain ToKdlChain(const LimbCase& c) {
  const Skeleton& s = c.skeleton;
  std::vector<int> path;
  for (int j = s.Find(c.effector); j != s.Find(c.root); j = s.parents[j]) path.insert(path.begin(), j);
  KDL::Chain chain;
  for (int j : path) {
    chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), ToKdl(s.rest[j].rotation, s.rest[j].translation)));
    const bool is_free = std::find(c.joints.begin(), c.joints.end(), s.names[j]) != c.joints.end();
    if (!is_free) continue;
    const JointLimit& l = *ik_rigs::FindLimit(c.limits, s.names[j]);
    if (l.kind == JointLimit::Kind::kSwingTwist && l.cone_deg == 0) {
      chain.addSegment(KDL::Segment(KDL::Joint(KDL::Vector::Zero(), ToKdl(l.axis.normalized()), KDL::Joint::RotAxis)));
    } else {
      const std::array<Axis, 3> order =
          l.kind == JointLimit::Kind::kEuler ? l.order : std::array<Axis, 3>{Axis::kZ, Axis::kY, Axis::kX};
      for (Axis a : order) chain.addSegment(KDL::Segment(KDL::Joint(RotationAbout(a))));
    }
  }
  chain.addSegment(KDL::Segment(KDL::Joint(KDL::Joint::None), KDL::Frame(ToKdl(c.offset))));
  return chain;
}

// The skeleton pose for KDL joint values (the chain's joints in order).
std::vector<Trs> PoseOf(const LimbCase& c, const KDL::JntArray& q) {
  std::vector<Trs> pose = c.skeleton.rest;
  unsigned k = 0;
  for (const std::string& name : c.joints) {  // top first, as in ToKdlChain
    const int j = c.skeleton.Find(name);
    const JointLimit& l = *ik_rigs::FindLimit(c.limits, name);
    Eigen::Quaterniond delta = Eigen::Quaterniond::Identity();
    if (l.kind == JointLimit::Kind::kSwingTwist && l.cone_deg == 0) {
      delta = Eigen::AngleAxisd(q(k++), l.axis.normalized());
    } else {
      const std::array<Axis, 3> order =
          l.kind == JointLimit::Kind::kEuler ? l.order : std::array<Axis, 3>{Axis::kZ, Axis::kY, Axis::kX};
      for (Axis a : order) delta = delta * AxisRotation(a, q(k++));
    }
    pose[j].rotation = c.skeleton.rest[j].rotation * delta;
  }
  return pose;
}

// KDL's stats, and in `within_limits` the share of targets it reached with
// a pose that happens to respect the rig's limits (it does not know them).
ik_bench::SolveStats MeasureKdl(const LimbCase& c, const std::vector<ik_rigs::Target>& targets, double* within_limits) {
  const KDL::Chain chain = ToKdlChain(c);
  // The chain's base is the root joint's world frame in the rest pose.
  std::vector<Eigen::Affine3d> world(c.skeleton.size());
  ComputeWorld(c.skeleton, c.skeleton.rest, world);
  const Eigen::Affine3d base_inverse = world[c.skeleton.Find(c.root)].inverse();
  const double l = c.chain_length;
  Eigen::Matrix<double, 6, 1> weights;
  weights << 1, 1, 1, c.with_rotation ? l : 0, c.with_rotation ? l : 0, c.with_rotation ? l : 0;
  // Position and weighted rotation each within 0.5e-3 × l when the norm of
  // both is within √2 × that.
  const double eps = 0.5e-3 * l * (c.with_rotation ? std::numbers::sqrt2 : 1.0);
  KDL::ChainIkSolverPos_LMA solver(chain, weights, eps, 500);
  KDL::ChainFkSolverPos_recursive fk(chain);
  std::vector<KDL::Frame> goals;
  for (const ik_rigs::Target& t : targets) {
    const Eigen::Quaterniond r(base_inverse.linear() * t.rotation.toRotationMatrix());
    goals.push_back(ToKdl(r, base_inverse * t.position));
  }
  const KDL::JntArray start(chain.getNrOfJoints());
  KDL::JntArray q(chain.getNrOfJoints());
  std::vector<KDL::JntArray> solutions(targets.size(), q);
  ik_bench::SolveStats stats = ik_bench::Measure(static_cast<int>(goals.size()), [&](int i) {
    solver.CartToJnt(start, goals[i], solutions[i]);
    return std::pair(true, solver.lastNrOfIter);
  });
  // Judge outside the timed loop, with KDL's own forward kinematics.
  int reached = 0, inside = 0;
  for (size_t i = 0; i < goals.size(); ++i) {
    KDL::Frame f;
    fk.JntToCart(solutions[i], f);
    const double position_error = (f.p - goals[i].p).Norm();
    const double rotation_error = KDL::diff(f.M, goals[i].M).Norm();
    const bool ok = ik_rigs::Reached(c, position_error, rotation_error);
    reached += ok;
    inside += ok && ik_rigs::WithinLimits(c.skeleton, c.limits, PoseOf(c, solutions[i]));
  }
  stats.success_percent = 100.0 * reached / static_cast<double>(goals.size());
  *within_limits = 100.0 * inside / static_cast<double>(goals.size());
  return stats;
}

void BM_IkVersusKdl(benchmark::State& state, const char* name) {
  const LimbCase c = ik_rigs::StandardCase(name);
  const std::vector<ik_rigs::Target> targets = ik_bench::ReachableTargets(c, ik_bench::kTargets, 2024);
  ik_bench::SolveStats ours, kdl;
  double kdl_within_limits = 0;
  for (auto _ : state) {
    ours = ik_bench::MeasureArmature(c, targets);
    kdl = MeasureKdl(c, targets, &kdl_within_limits);
  }
  ik_bench::Report(state, "armature_", ours);
  ik_bench::Report(state, "kdl_", kdl);
  // Reached and within the limits; for Armature that is its success rate
  // (its poses are always within them, see ik_dls_test.cc).
  state.counters["kdl_valid_%"] = kdl_within_limits;
  state.counters["speedup_median"] = kdl.median_us / ours.median_us;
  state.SetLabel(c.name);
}

BENCHMARK_CAPTURE(BM_IkVersusKdl, cmu_left_arm_reach, "cmu_left_arm_reach")
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IkVersusKdl, cmu_left_arm_pose, "cmu_left_arm_pose")->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IkVersusKdl, cmu_right_leg_reach, "cmu_right_leg_reach")
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IkVersusKdl, cmu_right_leg_pose, "cmu_right_leg_pose")
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(BM_IkVersusKdl, seven_dof_pose, "seven_dof_pose")->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace armature
