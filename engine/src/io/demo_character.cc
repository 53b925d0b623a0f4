#include "armature/engine/io/demo_character.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <tiny_gltf.h>

#include "armature/engine/mesh/auto_weights.h"
#include "armature/engine/io/demo_walk.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/mesh/mesh.h"
#include "armature/engine/math/rotation.h"
#include "io/gltf/gltf_export.h"

namespace armature {
namespace {

constexpr double kPi = std::numbers::pi;

// ---- The body: closed tubes around the bones (bind pose, centimetres) ----

// A cross-section: its distance along the tube's axis and its half-widths
// along the frame's u and v.
struct Section {
  double s, ru, rv;
};

// A closed surface swept along a straight axis, from a pole (first section,
// zero radius) to a pole (last section). Cross-sections are superellipses:
// exponent 2 is an ellipse, larger is boxier.
struct Tube {
  Eigen::Vector3d origin, axis, u, v;  // unit axis; u × v = axis
  std::vector<Section> sections;
  double exponent = 2;
  int segments = 20;  // vertices around each ring
};

constexpr int kCapRings = 5;          // rings per hemispherical cap, pole excluded
constexpr double kRingSpacing = 2.5;  // cm between rings along a limb

Tube Along(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction, const Eigen::Vector3d& hint) {
  Tube t;
  t.origin = origin;
  t.axis = direction.normalized();
  t.u = (hint - hint.dot(t.axis) * t.axis).normalized();
  t.v = t.axis.cross(t.u);
  return t;
}

// A circle of any radius: the frame's u only has to be perpendicular.
Tube AlongRound(const Eigen::Vector3d& origin, const Eigen::Vector3d& direction) {
  Eigen::Index smallest;
  direction.cwiseAbs().minCoeff(&smallest);
  return Along(origin, direction, Eigen::Vector3d::Unit(smallest));
}

// A tapered capsule from a (radius r0) to b (radius r1) with hemispherical caps.
Tube Capsule(const Eigen::Vector3d& a, const Eigen::Vector3d& b, double r0, double r1) {
  Tube t = AlongRound(a, b - a);
  const double length = (b - a).norm();
  for (int k = 0; k <= kCapRings; ++k) {
    const double angle = -kPi / 2 + kPi / 2 * k / kCapRings;
    t.sections.push_back({r0 * std::sin(angle), r0 * std::cos(angle), r0 * std::cos(angle)});
  }
  const int spans = std::max(1, static_cast<int>(std::lround(length / kRingSpacing)));
  for (int k = 1; k < spans; ++k) {
    const double f = static_cast<double>(k) / spans, r = r0 + (r1 - r0) * f;
    t.sections.push_back({length * f, r, r});
  }
  for (int k = 0; k <= kCapRings; ++k) {
    const double angle = kPi / 2 * k / kCapRings;
    t.sections.push_back({length + r1 * std::sin(angle), r1 * std::cos(angle), r1 * std::cos(angle)});
  }
  return t;
}

// An ellipsoid with half-length c along `direction` from its centre.
Tube Ellipsoid(const Eigen::Vector3d& centre, const Eigen::Vector3d& direction, const Eigen::Vector3d& hint, double c,
               double ru, double rv, int rings, int segments) {
  Tube t = Along(centre, direction, hint);
  t.origin = centre - c * t.axis;
  t.segments = segments;
  for (int k = 0; k <= rings; ++k) {
    const double angle = -kPi / 2 + kPi * k / rings;
    t.sections.push_back({c * (1 + std::sin(angle)), ru * std::cos(angle), rv * std::cos(angle)});
  }
  return t;
}

// The torso: a boxy tube from below the pelvis to the base of the neck whose
// half-width (x) and half-depth (z) follow keys by height, rounded off at both
// ends. Narrower than the shoulders' span so the hanging arms stay clear.
Tube Torso(double hips_y) {
  struct Key {
    double y, width, depth;
  };
  static constexpr Key kKeys[] = {{-16, 11.5, 8.5}, {-6, 13, 10},  {6, 11.5, 9}, {18, 11, 8.5},
                                  {30, 12, 10},     {42, 11.5, 9}, {48, 9, 7}};
  constexpr int kRings = 34;
  const double bottom = kKeys[0].y, top = std::end(kKeys)[-1].y;
  Tube t = Along({0, hips_y + bottom, 0}, Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitX());
  t.exponent = 3;
  t.segments = 32;
  for (int k = 0; k <= kRings; ++k) {
    const double f = (1 - std::cos(kPi * k / kRings)) / 2;  // rings closer together at the rounded ends
    const double y = bottom + f * (top - bottom);
    size_t i = 0;
    while (i + 2 < std::size(kKeys) && y > kKeys[i + 1].y) ++i;
    const Key &a = kKeys[i], &b = kKeys[i + 1];
    const double blend = (1 - std::cos(kPi * std::clamp((y - a.y) / (b.y - a.y), 0.0, 1.0))) / 2;
    const double rounding = std::pow(1 - std::pow(std::abs(2 * f - 1), 4.0), 0.25);
    t.sections.push_back({y - bottom, rounding * (a.width + blend * (b.width - a.width)),
                          rounding * (a.depth + blend * (b.depth - a.depth))});
  }
  return t;
}

void AddTube(const Tube& t, Mesh& mesh) {
  auto superellipse = [&](double c) { return std::copysign(std::pow(std::abs(c), 2 / t.exponent), c); };
  std::vector<uint32_t> first;  // first vertex of each section
  std::vector<bool> pole;
  for (const Section& section : t.sections) {
    first.push_back(static_cast<uint32_t>(mesh.positions.size()));
    const Eigen::Vector3d centre = t.origin + section.s * t.axis;
    pole.push_back(section.ru < 1e-9 && section.rv < 1e-9);
    if (pole.back()) {
      mesh.positions.push_back(centre.cast<float>());
      continue;
    }
    for (int k = 0; k < t.segments; ++k) {
      const double phi = 2 * kPi * k / t.segments;
      mesh.positions.push_back(
          (centre + section.ru * superellipse(std::cos(phi)) * t.u + section.rv * superellipse(std::sin(phi)) * t.v)
              .cast<float>());
    }
  }
  // Quads between consecutive sections, counter-clockwise seen from outside;
  // a pole is a ring whose vertices are all the same one.
  for (size_t i = 0; i + 1 < t.sections.size(); ++i) {
    auto at = [&](size_t section, int k) {
      return pole[section] ? first[section] : first[section] + static_cast<uint32_t>(k % t.segments);
    };
    for (int k = 0; k < t.segments; ++k) {
      const uint32_t a = at(i, k), b = at(i, k + 1), c = at(i + 1, k + 1), d = at(i + 1, k);
      if (!pole[i]) mesh.triangles.insert(mesh.triangles.end(), {a, b, c});
      if (!pole[i + 1]) mesh.triangles.insert(mesh.triangles.end(), {a, c, d});
    }
  }
}

// Arms hanging straight down would put each hand closer to the thigh's
// surface than the thigh bone is, and the automatic weights would let the
// hand move the thigh: the body is modelled and bound with the arms this far
// out (an A-pose), as characters usually are.
constexpr double kBindArmAbduction = 40 * kPi / 180;

Skeleton BindPose(const Skeleton& skeleton) {
  Skeleton bind = skeleton;
  for (const auto& [joint, sign] : {std::pair{"LeftShoulder", 1.0}, std::pair{"RightShoulder", -1.0}}) {
    Eigen::Quaterniond& rotation = bind.rest[static_cast<size_t>(bind.Find(joint))].rotation;
    rotation = Eigen::AngleAxisd(sign * kBindArmAbduction, Eigen::Vector3d::UnitZ()) * rotation;
  }
  return bind;
}

// The body, unbound, in the world space of `skeleton`'s rest pose.
Mesh MakeBody(const Skeleton& skeleton) {
  std::vector<Eigen::Affine3d> world(skeleton.size());
  ComputeWorld(skeleton, skeleton.rest, world);
  auto joint = [&](const char* name) { return world[static_cast<size_t>(skeleton.Find(name))]; };
  auto at = [&](const char* name) { return Eigen::Vector3d(joint(name).translation()); };
  auto end_site = [&](const char* name) {
    return Eigen::Vector3d(joint(name) * *skeleton.end_sites[static_cast<size_t>(skeleton.Find(name))]);
  };

  Mesh mesh;
  mesh.name = kDemoCharacterMeshName;
  AddTube(Torso(at("Hips").y()), mesh);
  AddTube(Capsule(at("Neck") - Eigen::Vector3d(0, 1, 0), at("Head") + Eigen::Vector3d(0, 2, 0), 5.0, 4.5), mesh);
  const Eigen::Vector3d crown = end_site("Head");
  AddTube(Ellipsoid(at("Head") + Eigen::Vector3d(0, 9, 1.5), crown - at("Head"), Eigen::Vector3d::UnitX(), 11, 8.5, 9.5,
                    20, 28),
          mesh);
  for (const std::string side : {"Left", "Right"}) {
    auto j = [&](const char* name) { return at((side + name).c_str()); };
    AddTube(Capsule(j("Hip"), j("Knee"), 7.0, 5.2), mesh);
    AddTube(Capsule(j("Knee"), j("Ankle"), 5.0, 3.6), mesh);
    AddTube(Capsule(j("Ankle"), j("Toe"), 3.8, 3.0), mesh);
    AddTube(Capsule(j("Toe"), end_site((side + "Toe").c_str()), 3.0, 2.4), mesh);
    // Shoulder: from the top of the torso out to the arm.
    const Eigen::Vector3d shoulder = j("Shoulder");
    AddTube(Capsule({std::copysign(6.0, shoulder.x()), shoulder.y() + 2, 0}, shoulder, 5.0, 5.0), mesh);
    AddTube(Capsule(shoulder, j("Elbow"), 4.6, 3.6), mesh);
    AddTube(Capsule(j("Elbow"), j("Wrist"), 3.5, 2.7), mesh);
    const Eigen::Vector3d hand = end_site((side + "Wrist").c_str()) - j("Wrist");
    AddTube(Ellipsoid(j("Wrist") + hand / 2, hand, Eigen::Vector3d::UnitX(), hand.norm() / 2, 2.0, 4.0, 12, 20), mesh);
  }
  mesh.normals = ComputeVertexNormals(mesh.positions, mesh.triangles);
  return mesh;
}

// ---- Writing the glb ----

// The model and its one buffer, as the glTF export builds them.
class GlbWriter : public gltf_export::ModelBuilder {
 public:
  GlbWriter() : ModelBuilder(0, "Armature demo character") {}
  StatusOr<std::string> Write() {
    auto glb = ModelBuilder::Write(true);
    if (!glb.ok()) return Status::Internal("demo character: tinygltf could not write the glb");
    return glb;
  }
};

void AddSkeleton(const Skeleton& skeleton, tinygltf::Model& model) {
  for (size_t j = 0; j < skeleton.size(); ++j) {
    tinygltf::Node node;
    node.name = skeleton.names[j];
    const Trs& rest = skeleton.rest[j];
    if (!rest.translation.isZero())
      node.translation = {rest.translation.x(), rest.translation.y(), rest.translation.z()};
    if (!rest.rotation.coeffs().isApprox(Eigen::Quaterniond::Identity().coeffs()))
      node.rotation = {rest.rotation.x(), rest.rotation.y(), rest.rotation.z(), rest.rotation.w()};
    model.nodes.push_back(node);
    if (skeleton.parents[j] >= 0) model.nodes[static_cast<size_t>(skeleton.parents[j])].children.push_back(int(j));
  }
  tinygltf::Scene scene;
  for (size_t j = 0; j < skeleton.size(); ++j)
    if (skeleton.parents[j] < 0) scene.nodes.push_back(static_cast<int>(j));
  model.scenes.push_back(scene);
  model.defaultScene = 0;
}

// The bound mesh and its skin, on the root node (see the header).
void AddSkinnedMesh(const Mesh& mesh, GlbWriter& glb) {
  const size_t n = mesh.vertex_count();
  std::vector<float> positions, normals, weights;
  std::vector<uint8_t> joints;
  std::vector<double> lo(3, 1e30), hi(3, -1e30);
  for (size_t v = 0; v < n; ++v) {
    for (int c = 0; c < 3; ++c) {
      positions.push_back(mesh.positions[v][c]);
      normals.push_back(mesh.normals[v][c]);
      lo[c] = std::min<double>(lo[c], mesh.positions[v][c]);
      hi[c] = std::max<double>(hi[c], mesh.positions[v][c]);
    }
    // Influences are sorted by weight, heaviest first; the heaviest takes the
    // float rounding so the four sum to 1 as closely as floats can.
    float w[4] = {0, 0, 0, 0};
    uint8_t j[4] = {0, 0, 0, 0};
    const uint32_t begin = mesh.influence_offsets[v], count = mesh.influence_offsets[v + 1] - begin;
    for (uint32_t k = 0; k < count; ++k) {
      j[k] = static_cast<uint8_t>(mesh.influence_joints[begin + k]);
      w[k] = mesh.influence_weights[begin + k];
    }
    w[0] = 1.f - (w[1] + w[2] + w[3]);
    joints.insert(joints.end(), j, j + 4);
    weights.insert(weights.end(), w, w + 4);
  }
  std::vector<uint16_t> indices(mesh.triangles.begin(), mesh.triangles.end());

  tinygltf::Primitive primitive;
  primitive.mode = TINYGLTF_MODE_TRIANGLES;
  primitive.attributes["POSITION"] =
      glb.Add(positions, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n, TINYGLTF_TARGET_ARRAY_BUFFER, lo, hi);
  primitive.attributes["NORMAL"] =
      glb.Add(normals, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, n, TINYGLTF_TARGET_ARRAY_BUFFER);
  primitive.attributes["JOINTS_0"] =
      glb.Add(joints, TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE, TINYGLTF_TYPE_VEC4, n, TINYGLTF_TARGET_ARRAY_BUFFER);
  primitive.attributes["WEIGHTS_0"] =
      glb.Add(weights, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, n, TINYGLTF_TARGET_ARRAY_BUFFER);
  primitive.indices = glb.Add(indices, TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT, TINYGLTF_TYPE_SCALAR, indices.size(),
                              TINYGLTF_TARGET_ELEMENT_ARRAY_BUFFER);

  std::vector<float> inverse_bind;
  for (const Eigen::Affine3d& m : mesh.inverse_bind) {
    const Eigen::Matrix4f f = m.matrix().cast<float>();  // column-major, as glTF
    inverse_bind.insert(inverse_bind.end(), f.data(), f.data() + 16);
  }
  tinygltf::Skin skin;
  skin.joints = mesh.joints;
  skin.skeleton = 0;
  skin.inverseBindMatrices =
      glb.Add(inverse_bind, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_MAT4, mesh.joints.size(), 0);

  tinygltf::Model& model = glb.model();
  tinygltf::Mesh gltf_mesh;
  gltf_mesh.name = mesh.name;
  gltf_mesh.primitives.push_back(primitive);
  model.meshes.push_back(gltf_mesh);
  model.skins.push_back(skin);
  model.nodes[0].mesh = 0;
  model.nodes[0].skin = 0;
}

// The clip's frames as LINEAR samplers: every joint's rotation, the roots' translations.
void AddAnimation(const Clip& clip, GlbWriter& glb) {
  tinygltf::Animation animation;
  animation.name = kDemoCharacterAnimationName;
  auto sampler = [&](int output, int node, const char* path, int input) {
    tinygltf::AnimationSampler s;
    s.input = input;
    s.output = output;
    s.interpolation = "LINEAR";
    animation.samplers.push_back(s);
    tinygltf::AnimationChannel c;
    c.sampler = static_cast<int>(animation.samplers.size()) - 1;
    c.target_node = node;
    c.target_path = path;
    animation.channels.push_back(c);
  };
  // Tracks with the same key times share one input accessor.
  std::vector<std::pair<std::vector<double>, int>> inputs;
  auto times = [&](const std::vector<double>& t) {
    for (const auto& [keys, accessor] : inputs)
      if (keys == t) return accessor;
    const std::vector<float> f(t.begin(), t.end());
    inputs.emplace_back(
        t, glb.Add(f, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_SCALAR, f.size(), 0, {f.front()}, {f.back()}));
    return inputs.back().second;
  };
  const Skeleton& skeleton = *clip.skeleton;
  for (size_t j = 0; j < skeleton.size(); ++j) {
    const QuatTrack& rotation = clip.joints[j].rotation;
    std::vector<float> xyzw;
    Eigen::Quaterniond previous = Eigen::Quaterniond::Identity();
    for (const Eigen::Quaterniond& value : rotation.values) {
      const Eigen::Quaterniond q = SameHemisphere(value, previous);  // one hemisphere: no spin on slerp
      previous = q;
      xyzw.insert(xyzw.end(), {float(q.x()), float(q.y()), float(q.z()), float(q.w())});
    }
    sampler(glb.Add(xyzw, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC4, rotation.values.size(), 0), int(j),
            "rotation", times(rotation.times));
    const Vec3Track& translation = clip.joints[j].translation;
    if (translation.empty()) continue;
    std::vector<float> xyz;
    for (const Eigen::Vector3d& p : translation.values)
      xyz.insert(xyz.end(), {float(p.x()), float(p.y()), float(p.z())});
    sampler(glb.Add(xyz, TINYGLTF_COMPONENT_TYPE_FLOAT, TINYGLTF_TYPE_VEC3, translation.values.size(), 0), int(j),
            "translation", times(translation.times));
  }
  glb.model().animations.push_back(animation);
}

}  // namespace

StatusOr<std::string> MakeDemoCharacterGlb() {
  const BvhData walk = MakeDemoWalk();
  BindOptions options;
  options.method = WeightMethod::kHeat;
  options.max_influences = 4;
  const Skeleton bind_pose = BindPose(*walk.skeleton);
  auto bound = BindMesh(MakeBody(bind_pose), bind_pose, options);
  if (!bound.ok()) return bound.status().WithContext("demo character: ");
  if (bound->mesh.vertex_count() > UINT16_MAX)
    return Status::Internal("demo character: too many vertices for 16-bit indices");

  GlbWriter glb;
  AddSkeleton(*walk.skeleton, glb.model());
  AddSkinnedMesh(bound->mesh, glb);
  AddAnimation(*walk.clip, glb);
  return glb.Write();
}

}  // namespace armature
