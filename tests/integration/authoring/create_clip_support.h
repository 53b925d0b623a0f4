// What the CreateClip tests share: keys made up by a seeded generator, the
// call, and a joint's local transform sampled through EvaluateClip.
#pragma once

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "armature/client.h"

namespace armature::testing {

// One joint's local transform as the server answers it (floats).
struct Local {
  Eigen::Vector3d translation;
  Eigen::Quaterniond rotation;  // normalized, sign as answered
};

// `joint` of `clip` (local space) at each of `times`, in one call.
inline std::vector<Local> SampleLocal(client::Client& client, const std::string& clip, const std::string& joint,
                                      const std::vector<double>& times) {
  v1::EvaluateClipRequest r;
  r.set_clip(clip);
  r.set_space(v1::LOCAL);
  r.add_joints(joint);
  for (double t : times) r.add_times(t);
  const auto response = client.EvaluateClip(r);
  std::vector<Local> out;
  for (const v1::Pose& p : response.poses()) {
    Local l;
    l.translation = Eigen::Vector3d(p.translations(0), p.translations(1), p.translations(2));
    l.rotation = Eigen::Quaterniond(p.rotations(0), p.rotations(1), p.rotations(2), p.rotations(3));
    out.push_back(l);
  }
  return out;
}

// Two demo walks blended, the second shifted by 0.4 s at `second_weight`:
// a pose no clip has, for the bake tests.
inline v1::Motion TwoWalksBlend(double second_weight) {
  v1::Motion m;
  m.add_layers()->set_clip("demo_walk");
  v1::MotionLayer* second = m.add_layers();
  second->set_clip("demo_walk");
  second->set_time_offset(0.4);
  second->set_weight(second_weight);
  return m;
}

// Made-up keys, reproducible: uneven times, unit quaternions, translations in [-2, 2].
struct KeyMaker {
  std::mt19937 rng{1234};
  double Uniform(double a, double b) { return std::uniform_real_distribution<double>(a, b)(rng); }
  // On a 1/4096 s grid, which 32-bit floats (glTF's times) hold exactly: a
  // time a float rounds moves the key by up to 1e-7 s, and a value changing
  // at 20/s by 2e-6, more than the 1e-6 the keys are checked to.
  std::vector<double> Times(int n) {
    std::vector<double> t = {Uniform(0, 0.2)};
    for (int k = 1; k < n; ++k) t.push_back(t.back() + Uniform(0.15, 0.6));
    for (double& x : t) x = std::round(x * 4096) / 4096;
    return t;
  }
  Eigen::Quaterniond Rotation() {
    Eigen::Vector4d v(Uniform(-1, 1), Uniform(-1, 1), Uniform(-1, 1), Uniform(-1, 1));
    return Eigen::Quaterniond(v.normalized());  // coefficients x, y, z, w
  }
  Eigen::Vector3d Translation() { return Eigen::Vector3d(Uniform(-2, 2), Uniform(-2, 2), Uniform(-2, 2)); }
};

// A JointKeys from values (rotations w, x, y, z on the wire).
inline v1::JointKeys Keys(const std::string& joint, const std::vector<double>& times,
                          const std::vector<Eigen::Quaterniond>& rotations,
                          const std::vector<Eigen::Vector3d>& translations, v1::Interpolation mode) {
  v1::JointKeys k;
  k.set_joint(joint);
  k.set_interpolation(mode);
  for (double t : times) k.add_times(t);
  for (const auto& q : rotations)
    for (double c : {q.w(), q.x(), q.y(), q.z()}) k.add_rotations(c);
  for (const auto& p : translations)
    for (double c : {p.x(), p.y(), p.z()}) k.add_translations(c);
  return k;
}

// |a − b| within `rel` of the larger magnitude (at least 1): float storage
// keeps about 7 digits, so equality is relative.
inline bool CloseRelative(double a, double b, double rel) {
  return std::abs(a - b) <= rel * std::max({1.0, std::abs(a), std::abs(b)});
}

// q or −q, whichever is nearer `reference` (the same rotation).
inline Eigen::Vector4d Aligned(const Eigen::Quaterniond& q, const Eigen::Quaterniond& reference) {
  return q.coeffs().dot(reference.coeffs()) < 0 ? Eigen::Vector4d(-q.coeffs()) : Eigen::Vector4d(q.coeffs());
}

}  // namespace armature::testing
