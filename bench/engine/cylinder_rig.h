// The skinning benchmarks' rig: a cylinder along a 64-joint chain, every
// vertex with exactly 4 influences, posed with a bend and a twist on every
// joint. Shared by skinning_bench.cc and vs_ozz_bench.cc so both skin the
// same mesh.
#pragma once

#include <map>
#include <memory>
#include <utility>
#include <vector>

#include "../../tests/engine/testing/mesh_test_util.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/math/rotation.h"
#include "armature/engine/mesh/mesh.h"

namespace armature_bench {

struct CylinderRig {
  std::shared_ptr<armature::Skeleton> skeleton;
  armature::Mesh mesh;
  std::vector<Eigen::Affine3d> world;  // the posed joints
};

// 64 segments per ring; built once per (rings, morph) and cached.
inline const CylinderRig& MakeCylinderRig(int rings, bool morph) {
  using namespace armature;
  static std::map<std::pair<int, bool>, CylinderRig> cache;
  auto [it, fresh] = cache.try_emplace({rings, morph});
  CylinderRig& rig = it->second;
  if (!fresh) return rig;
  const int joints = 64, segments = 64;
  const double length = 0.25;
  rig.skeleton = test_util::MakeChain(joints, length);
  rig.mesh = test_util::MakeCylinder(0.1, joints * length, rings, segments);
  test_util::BindAlongZ(rig.mesh, *rig.skeleton, length, 4);
  if (morph) {
    MorphTarget t{"bulge", {}, {}, {}};
    for (uint32_t v = 0; v < rig.mesh.vertex_count(); v += 10) {
      t.vertices.push_back(v);
      t.position_deltas.emplace_back(0.01f, 0, 0);
    }
    rig.mesh.targets.push_back(t);
    rig.mesh.default_weights = {0.5f};
  }
  if (!FinalizeMesh(rig.mesh).ok()) std::abort();
  std::vector<Trs> pose = rig.skeleton->rest;
  for (size_t i = 0; i < pose.size(); ++i)
    pose[i].rotation = AxisRotation(Axis::kX, 0.05) * AxisRotation(Axis::kZ, 0.1 * static_cast<double>(i % 5));
  rig.world.resize(pose.size());
  ComputeWorld(*rig.skeleton, pose, rig.world);
  return rig;
}

}  // namespace armature_bench
