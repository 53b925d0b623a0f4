// The motion blend's float lanes: which joints blend in float, grouped four
// by four per property (bound once), and the blend itself, three.js's
// PropertyMixer.accumulate / apply on four joints per vector.
#include "anim/motion_float_blend.h"

#include <algorithm>

#include "anim/compression/simd4.h"
#include "anim/slerp_flat4.h"

namespace armature::motion_internal {
namespace {

enum Property { kRotation, kTranslation, kScale };

// Where property `p` of joint `j` sits in a pose's lanes of `joints` joints (4, 3, 3 floats a joint).
uint32_t LaneOffset(int p, size_t joints, uint32_t j) {
  return static_cast<uint32_t>(p == kRotation ? 4 * j : (p == kTranslation ? 4 : 7) * joints + 3 * j);
}

// Per clip joint, the properties a track (animated or constant) holds (bit 0 rotation, 1 translation, 2 scale).
std::vector<uint8_t> TrackedParts(const CompressedClip& clip) {
  std::vector<uint8_t> parts(clip.skeleton->size(), 0);
  for (const AnimatedTrack& t : clip.animated) parts[t.joint] |= static_cast<uint8_t>(1 << static_cast<int>(t.kind));
  for (const ConstantTrack& t : clip.constants) parts[t.joint] |= static_cast<uint8_t>(1 << static_cast<int>(t.kind));
  return parts;
}

bool SameProperty(int p, const Trs& a, const Trs& b) {
  if (p == kRotation) return a.rotation.coeffs() == b.rotation.coeffs();
  return p == kTranslation ? a.translation == b.translation : a.scale == b.scale;
}

// A float joint's property: the sources of the layers animating it, in layer order.
struct PropertySources {
  uint32_t joint = 0;
  std::vector<FloatBlendSource> sources;
};

// Property `p` of every float joint a layer animates with something else than the rest value.
std::vector<PropertySources> AnimatedProperty(const MotionPlan& plan, int p,
                                              const std::vector<std::vector<uint8_t>>& tracked) {
  std::vector<PropertySources> out;
  const FloatBlendPlan& fb = plan.float_blend;
  for (uint32_t j = 0; j < fb.float_joint.size(); ++j) {
    if (!fb.float_joint[j]) continue;
    PropertySources ps{j, {}};
    bool all_rest = true;
    for (uint32_t e = plan.joint_begin[j]; e < plan.joint_begin[j + 1]; ++e) {
      const JointLayer& entry = plan.joint_layers[e];
      if (!(entry.parts >> p & 1)) continue;
      const CompressedClip& clip = *plan.layers[entry.layer].clip;
      all_rest = all_rest && !(tracked[entry.layer][entry.joint] >> p & 1) &&
                 SameProperty(p, clip.skeleton->rest[entry.joint], plan.skeleton->rest[j]);
      ps.sources.push_back({entry.layer, LaneOffset(p, clip.skeleton->size(), entry.joint)});
    }
    if (!ps.sources.empty() && !all_rest) out.push_back(std::move(ps));
  }
  return out;
}

// Those properties four by four, joints with as many layers together.
std::vector<FloatBlendGroup> Group(std::vector<PropertySources> list, std::vector<FloatBlendSource>& sources) {
  std::stable_sort(list.begin(), list.end(), [](const PropertySources& a, const PropertySources& b) {
    return a.sources.size() < b.sources.size();
  });
  std::vector<FloatBlendGroup> groups;
  for (size_t i = 0; i < list.size();) {
    FloatBlendGroup g;
    g.steps = static_cast<uint32_t>(list[i].sources.size());
    while (g.lanes < 4 && i + g.lanes < list.size() && list[i + g.lanes].sources.size() == g.steps) ++g.lanes;
    g.first = static_cast<uint32_t>(sources.size());
    for (uint32_t lane = 0; lane < 4; ++lane) g.joints[lane] = list[i + std::min(lane, g.lanes - 1)].joint;
    for (uint32_t k = 0; k < g.steps; ++k)
      for (uint32_t lane = 0; lane < 4; ++lane) sources.push_back(list[i + std::min(lane, g.lanes - 1)].sources[k]);
    groups.push_back(g);
    i += g.lanes;
  }
  return groups;
}

template <int N>
struct Lanes {
  v4 c[N];
};

// Four vectors' transpose: a b c d as rows become the columns.
inline void Transpose(v4 a, v4 b, v4 c, v4 d, v4 out[4]) {
  const v4 ab_low = __builtin_shufflevector(a, b, 0, 4, 1, 5), ab_high = __builtin_shufflevector(a, b, 2, 6, 3, 7);
  const v4 cd_low = __builtin_shufflevector(c, d, 0, 4, 1, 5), cd_high = __builtin_shufflevector(c, d, 2, 6, 3, 7);
  out[0] = __builtin_shufflevector(ab_low, cd_low, 0, 1, 4, 5);
  out[1] = __builtin_shufflevector(ab_low, cd_low, 2, 3, 6, 7);
  out[2] = __builtin_shufflevector(ab_high, cd_high, 0, 1, 4, 5);
  out[3] = __builtin_shufflevector(ab_high, cd_high, 2, 3, 6, 7);
}

// Four joints' N floats (lane i's at p[i], four readable: lanes are padded)
// as N vectors.
template <int N>
Lanes<N> Gather(const float* const p[4]) {
  v4 columns[4];
  Transpose(Load4(p[0]), Load4(p[1]), Load4(p[2]), Load4(p[3]), columns);
  Lanes<N> v;
  for (int c = 0; c < N; ++c) v.c[c] = columns[c];
  return v;
}

// The other way, written in double: lane i's rotation made unit (as a
// sampled rotation, rotation_batch.h: the float blend leaves |q| − 1 near
// 1e-7) or its vector, to lane i's joint, straight from the registers.
void StoreRotations(const Lanes<4>& v, const FloatBlendGroup& g, std::span<Trs> output) {
  v4 rows[4];
  Transpose(v.c[0], v.c[1], v.c[2], v.c[3], rows);
  for (uint32_t i = 0; i < g.lanes; ++i)
    compression_internal::StoreUnitDouble(rows[i], output[g.joints[i]].rotation.coeffs().data());  // x y z w
}

void StoreVectors(const Lanes<3>& v, const FloatBlendGroup& g, Eigen::Vector3d Trs::*member, std::span<Trs> output) {
  v4 rows[4];
  Transpose(v.c[0], v.c[1], v.c[2], Splat(0.f), rows);
  for (uint32_t i = 0; i < g.lanes; ++i) {
    double* to = (output[g.joints[i]].*member).data();
    to[0] = rows[i][0], to[1] = rows[i][1], to[2] = rows[i][2];
  }
}

// PropertyMixer's mix: slerpFlat for rotations, lerp for vectors.
template <int N>
Lanes<N> Mix(const Lanes<N>& a, const Lanes<N>& b, v4 t) {
  Lanes<N> r;
  if constexpr (N == 4) {
    SlerpFlat4(a.c, b.c, t, r.c);
  } else {
    for (int c = 0; c < N; ++c) r.c[c] = a.c[c] * (Splat(1.f) - t) + b.c[c] * t;
  }
  return r;
}

template <int N>
Lanes<N> Choose(v4i mask, const Lanes<N>& yes, const Lanes<N>& no) {
  Lanes<N> r;
  for (int c = 0; c < N; ++c) r.c[c] = Select(mask, yes.c[c], no.c[c]);
  return r;
}

bool Any(v4i mask) { return (mask[0] | mask[1] | mask[2] | mask[3]) != 0; }

// One group's property: the layers accumulated in order (the first taken as
// it is while the weight so far is 0, each next one mixed in by its weight
// over the weight so far), then a total below 1 filled with the rest value.
template <int N>
Lanes<N> BlendGroup(const MotionPlan& plan, const MotionWorkspace& ws, const FloatBlendGroup& g, int p) {
  const FloatBlendPlan& fb = plan.float_blend;
  Lanes<N> value{};
  v4 total = Splat(0.f);  // set by the first step (a group has one at least)
  for (uint32_t k = 0; k < g.steps; ++k) {
    const FloatBlendSource* s = &fb.sources[g.first + 4 * k];
    const float* at[4];
    v4 w;
    for (int i = 0; i < 4; ++i) {
      at[i] = ws.layer_lanes[s[i].layer].data() + s[i].offset;
      w[i] = static_cast<float>(plan.layers[s[i].layer].joint_weight[g.joints[i]]);
    }
    const Lanes<N> v = Gather<N>(at);
    if (k == 0) {
      value = v, total = w;
      continue;
    }
    const v4 sum = total + w;
    value = Choose(total == Splat(0.f), v, Mix(value, v, w / sum));
    total = sum;
  }
  const v4i short_of_one = total < Splat(1.f);
  if (!Any(short_of_one)) return value;
  const float* at[4];
  for (int i = 0; i < 4; ++i) at[i] = fb.rest.data() + LaneOffset(p, plan.skeleton->size(), g.joints[i]);
  const Lanes<N> rest = Gather<N>(at);
  const Lanes<N> filled = Choose(total == Splat(0.f), rest, Mix(value, rest, Splat(1.f) - total));
  return Choose(short_of_one, filled, value);
}

}  // namespace

void BindFloatBlend(MotionPlan& plan) {
  FloatBlendPlan& fb = plan.float_blend;
  const size_t n = plan.skeleton->size();
  fb.float_joint.assign(n, 0);
  for (size_t j = 0; j < n; ++j) {
    const JointLayer* begin = plan.joint_layers.data() + plan.joint_begin[j];
    const JointLayer* end = plan.joint_layers.data() + plan.joint_begin[j + 1];
    fb.float_joint[j] =
        begin != end && static_cast<int>(j) != plan.root && std::all_of(begin, end, [&](const JointLayer& e) {
          return !e.additive && !plan.layers[e.layer].clip->exact();
        });
    if (fb.float_joint[j])
      for (const JointLayer* e = begin; e != end; ++e) plan.layers[e->layer].float_lanes = true;
  }
  std::vector<std::vector<uint8_t>> tracked;
  for (const BoundLayer& l : plan.layers) tracked.push_back(TrackedParts(*l.clip));
  fb.rotations = Group(AnimatedProperty(plan, kRotation, tracked), fb.sources);
  fb.translations = Group(AnimatedProperty(plan, kTranslation, tracked), fb.sources);
  fb.scales = Group(AnimatedProperty(plan, kScale, tracked), fb.sources);
  fb.rest.assign(10 * n + 1, 0.f);  // padded: four floats load from the last
  for (uint32_t j = 0; j < n; ++j) {
    const Trs& r = plan.skeleton->rest[j];
    const double q[4] = {r.rotation.x(), r.rotation.y(), r.rotation.z(), r.rotation.w()};
    for (int c = 0; c < 4; ++c) fb.rest[LaneOffset(kRotation, n, j) + c] = static_cast<float>(q[c]);
    for (int c = 0; c < 3; ++c) {
      fb.rest[LaneOffset(kTranslation, n, j) + c] = static_cast<float>(r.translation[c]);
      fb.rest[LaneOffset(kScale, n, j) + c] = static_cast<float>(r.scale[c]);
    }
  }
}

void BlendFloatJoints(const MotionPlan& plan, const MotionWorkspace& workspace, std::span<Trs> output) {
  const FloatBlendPlan& fb = plan.float_blend;
  for (const FloatBlendGroup& g : fb.rotations) StoreRotations(BlendGroup<4>(plan, workspace, g, kRotation), g, output);
  for (const FloatBlendGroup& g : fb.translations)
    StoreVectors(BlendGroup<3>(plan, workspace, g, kTranslation), g, &Trs::translation, output);
  for (const FloatBlendGroup& g : fb.scales)
    StoreVectors(BlendGroup<3>(plan, workspace, g, kScale), g, &Trs::scale, output);
}

}  // namespace armature::motion_internal
