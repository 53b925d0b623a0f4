#include "server/rpc/convert/pose_convert.h"

#include "armature/engine/kinematics/fk.h"

namespace armature::server {

void ToProto(const Skeleton& s, v1::Skeleton* out) {
  for (size_t i = 0; i < s.size(); ++i) {
    v1::Joint* j = out->add_joints();
    j->set_name(s.names[i]);
    j->set_parent(s.parents[i]);
    const Trs& r = s.rest[i];
    for (int k = 0; k < 3; ++k) j->add_offset(static_cast<float>(r.translation[k]));
    j->add_rest_rotation(static_cast<float>(r.rotation.w()));
    for (int k = 0; k < 3; ++k) j->add_rest_rotation(static_cast<float>(r.rotation.vec()[k]));
    for (int k = 0; k < 3; ++k) j->add_rest_scale(static_cast<float>(r.scale[k]));
    for (Channel c : s.channels[i]) j->add_channels(std::string(ChannelName(c)));
    if (s.end_sites[i])
      for (int k = 0; k < 3; ++k) j->add_end_site(static_cast<float>((*s.end_sites[i])[k]));
  }
}

std::optional<Interpolation> FromProto(v1::Interpolation i) {
  switch (i) {
    case v1::STEP: return Interpolation::kStep;
    case v1::LINEAR: return Interpolation::kLinear;
    case v1::CUBIC: return Interpolation::kCubic;
    default: return std::nullopt;
  }
}

v1::Interpolation ToProto(Interpolation i) {
  switch (i) {
    case Interpolation::kStep: return v1::STEP;
    case Interpolation::kLinear: return v1::LINEAR;
    case Interpolation::kCubic: return v1::CUBIC;
  }
  return v1::INTERPOLATION_UNSPECIFIED;
}

WrapMode FromProto(v1::WrapMode w) { return w == v1::LOOP ? WrapMode::kLoop : WrapMode::kClamp; }

void PackPose(const Skeleton& skeleton, v1::Space space, std::span<const int> joints, PoseWorkspace& ws,
              v1::Pose* out) {
  const int n = static_cast<int>(joints.size());
  auto* t = out->mutable_translations();
  auto* r = out->mutable_rotations();
  t->Reserve(3 * n);
  r->Reserve(4 * n);
  auto put = [&](const Eigen::Vector3d& p, const Eigen::Quaterniond& q) {
    for (int k = 0; k < 3; ++k) t->AddAlreadyReserved(static_cast<float>(p[k]));
    r->AddAlreadyReserved(static_cast<float>(q.w()));
    for (int k = 0; k < 3; ++k) r->AddAlreadyReserved(static_cast<float>(q.vec()[k]));
  };
  if (space == v1::WORLD) {
    ComputeWorld(skeleton, ws.local, ws.world, ws.world_rotation);
    for (int j : joints) put(ws.world[j].translation(), ws.world_rotation[j]);
    return;
  }
  bool scaled = false;
  for (int j : joints) {
    put(ws.local[j].translation, ws.local[j].rotation);
    scaled = scaled || !ws.local[j].scale.isOnes(1e-9);
  }
  if (scaled) {
    auto* s = out->mutable_scales();
    s->Reserve(3 * n);
    for (int j : joints)
      for (int k = 0; k < 3; ++k) s->AddAlreadyReserved(static_cast<float>(ws.local[j].scale[k]));
  }
}

}  // namespace armature::server
