// An independent BVH model for tests: a plain iostream reader and writer and
// forward kinematics from explicit 4×4 matrices built with cos/sin, with its
// own matrix→quaternion and slerp. It shares no code with the engine, so the
// engine's parser, rotation code and sampling are checked against it.
#pragma once

#include <algorithm>
#include <cctype>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <optional>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <gtest/gtest.h>

#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/kinematics/fk.h"
#include "armature/engine/anim/skeleton.h"

namespace armature::testing {

struct RefJoint {
  std::string name;
  int parent = -1;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  std::vector<std::string> channels;  // "Xposition" … "Zrotation", file order
  std::optional<Eigen::Vector3d> end_site;
};

struct RefBvh {
  std::vector<RefJoint> joints;  // depth-first, as in the file
  double frame_time = 1.0 / 30.0;
  std::vector<std::vector<double>> frames;  // one value per channel, joints in order
};

// Trusting reader for well-formed files (the test's own and the CMU file).
inline RefBvh ReadRefBvh(const std::string& text) {
  RefBvh bvh;
  std::istringstream in(text);
  std::string tok;
  std::vector<int> stack;
  bool in_end_site = false;
  while (in >> tok) {
    if (tok == "ROOT" || tok == "JOINT") {
      RefJoint j;
      in >> j.name;
      j.parent = stack.empty() ? -1 : stack.back();
      bvh.joints.push_back(j);
      stack.push_back(static_cast<int>(bvh.joints.size()) - 1);
    } else if (tok == "End") {
      in >> tok;  // Site
      in_end_site = true;
    } else if (tok == "OFFSET") {
      Eigen::Vector3d o;
      in >> o.x() >> o.y() >> o.z();
      if (in_end_site)
        bvh.joints[static_cast<size_t>(stack.back())].end_site = o;
      else
        bvh.joints[static_cast<size_t>(stack.back())].offset = o;
    } else if (tok == "CHANNELS") {
      int n;
      in >> n;
      auto& ch = bvh.joints[static_cast<size_t>(stack.back())].channels;
      ch.resize(static_cast<size_t>(n));
      for (auto& c : ch) in >> c;
    } else if (tok == "}") {
      if (in_end_site)
        in_end_site = false;
      else
        stack.pop_back();
    } else if (tok == "MOTION") {
      break;
    }
  }
  size_t columns = 0;
  for (const auto& j : bvh.joints) columns += j.channels.size();
  int frames;
  in >> tok >> frames;                 // Frames: N
  in >> tok >> tok >> bvh.frame_time;  // Frame Time: T
  bvh.frames.assign(static_cast<size_t>(frames), std::vector<double>(columns));
  for (auto& f : bvh.frames)
    for (double& v : f) in >> v;
  return bvh;
}

inline std::string WriteRefBvh(const RefBvh& bvh) {
  std::ostringstream out;
  out << std::setprecision(17);
  out << "HIERARCHY\n";
  std::vector<int> open;
  auto close = [&] {
    const RefJoint& j = bvh.joints[static_cast<size_t>(open.back())];
    if (j.end_site)
      out << "End Site\n{\nOFFSET " << j.end_site->x() << " " << j.end_site->y() << " " << j.end_site->z() << "\n}\n";
    out << "}\n";
    open.pop_back();
  };
  for (size_t i = 0; i < bvh.joints.size(); ++i) {
    const RefJoint& j = bvh.joints[i];
    while (!open.empty() && open.back() != j.parent) close();
    out << (j.parent < 0 ? "ROOT " : "JOINT ") << j.name << "\n{\nOFFSET " << j.offset.x() << " " << j.offset.y() << " "
        << j.offset.z() << "\nCHANNELS " << j.channels.size();
    for (const auto& c : j.channels) out << " " << c;
    out << "\n";
    open.push_back(static_cast<int>(i));
  }
  while (!open.empty()) close();
  out << "MOTION\nFrames: " << bvh.frames.size() << "\nFrame Time: " << bvh.frame_time << "\n";
  for (const auto& f : bvh.frames) {
    for (size_t k = 0; k < f.size(); ++k) out << (k ? " " : "") << f[k];
    out << "\n";
  }
  return out.str();
}

// Rotation about a coordinate axis, written out from cos/sin.
inline Eigen::Matrix3d RefAxisMatrix(char axis, double degrees) {
  const double a = degrees * std::numbers::pi / 180.0, c = std::cos(a), s = std::sin(a);
  Eigen::Matrix3d m;
  switch (axis) {
    case 'X': m << 1, 0, 0, 0, c, -s, 0, s, c; break;
    case 'Y': m << c, 0, s, 0, 1, 0, -s, 0, c; break;
    default: m << c, -s, 0, s, c, 0, 0, 0, 1; break;
  }
  return m;
}

// A joint's local rotation and translation at one frame: channels compose in
// file order, position channels add to the OFFSET.
struct RefLocal {
  Eigen::Matrix3d rotation;
  Eigen::Vector3d translation;
};

inline std::vector<RefLocal> RefLocals(const RefBvh& bvh, size_t frame) {
  std::vector<RefLocal> locals;
  size_t col = 0;
  for (const RefJoint& j : bvh.joints) {
    RefLocal l{Eigen::Matrix3d::Identity(), j.offset};
    for (const std::string& c : j.channels) {
      const double v = bvh.frames[frame][col++];
      const char axis = static_cast<char>(std::toupper(static_cast<unsigned char>(c[0])));
      if (c.find("rotation") != std::string::npos)
        l.rotation = l.rotation * RefAxisMatrix(axis, v);
      else
        l.translation[axis - 'X'] += v;
    }
    locals.push_back(l);
  }
  return locals;
}

inline Eigen::Matrix4d RefHomogeneous(const RefLocal& l) {
  Eigen::Matrix4d m = Eigen::Matrix4d::Identity();
  m.topLeftCorner<3, 3>() = l.rotation;
  m.topRightCorner<3, 1>() = l.translation;
  return m;
}

inline std::vector<Eigen::Vector3d> RefWorldPositions(const RefBvh& bvh, const std::vector<RefLocal>& locals) {
  std::vector<Eigen::Matrix4d> world(locals.size());
  std::vector<Eigen::Vector3d> pos(locals.size());
  for (size_t i = 0; i < locals.size(); ++i) {
    const int p = bvh.joints[i].parent;
    world[i] =
        p < 0 ? RefHomogeneous(locals[i]) : Eigen::Matrix4d(world[static_cast<size_t>(p)] * RefHomogeneous(locals[i]));
    pos[i] = world[i].topRightCorner<3, 1>();
  }
  return pos;
}

// Quaternion (w, x, y, z) of a rotation matrix, Shepperd's method.
inline Eigen::Vector4d RefMatrixToQuat(const Eigen::Matrix3d& m) {
  const double tr = m.trace();
  Eigen::Vector4d q;
  if (tr > 0) {
    const double s = 2 * std::sqrt(1 + tr);
    q << 0.25 * s, (m(2, 1) - m(1, 2)) / s, (m(0, 2) - m(2, 0)) / s, (m(1, 0) - m(0, 1)) / s;
  } else if (m(0, 0) > m(1, 1) && m(0, 0) > m(2, 2)) {
    const double s = 2 * std::sqrt(1 + m(0, 0) - m(1, 1) - m(2, 2));
    q << (m(2, 1) - m(1, 2)) / s, 0.25 * s, (m(0, 1) + m(1, 0)) / s, (m(0, 2) + m(2, 0)) / s;
  } else if (m(1, 1) > m(2, 2)) {
    const double s = 2 * std::sqrt(1 + m(1, 1) - m(0, 0) - m(2, 2));
    q << (m(0, 2) - m(2, 0)) / s, (m(0, 1) + m(1, 0)) / s, 0.25 * s, (m(1, 2) + m(2, 1)) / s;
  } else {
    const double s = 2 * std::sqrt(1 + m(2, 2) - m(0, 0) - m(1, 1));
    q << (m(1, 0) - m(0, 1)) / s, (m(0, 2) + m(2, 0)) / s, (m(1, 2) + m(2, 1)) / s, 0.25 * s;
  }
  return q.normalized();
}

inline Eigen::Matrix3d RefQuatToMatrix(const Eigen::Vector4d& q) {
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  Eigen::Matrix3d m;
  m << 1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y),  //
      2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x),   //
      2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y);
  return m;
}

// Textbook slerp on (w, x, y, z) vectors along the shorter arc.
inline Eigen::Vector4d RefSlerp(const Eigen::Vector4d& a, Eigen::Vector4d b, double t) {
  double d = a.dot(b);
  if (d < 0) {
    b = -b;
    d = -d;
  }
  if (d > 1 - 1e-15) return ((1 - t) * a + t * b).normalized();
  const double theta = std::acos(d);
  return (std::sin((1 - t) * theta) * a + std::sin(t * theta) * b) / std::sin(theta);
}

// World joint positions at any time: the neighbouring frames' local
// rotations slerped, translations lerped, then matrix FK. Clamped to the clip.
inline std::vector<Eigen::Vector3d> RefWorldPositionsAt(const RefBvh& bvh, double time) {
  const size_t n = bvh.frames.size();
  const double x = std::clamp(time / bvh.frame_time, 0.0, static_cast<double>(n - 1));
  const size_t i = std::min(static_cast<size_t>(std::floor(x)), n - 1);
  const double u = x - static_cast<double>(i);
  std::vector<RefLocal> a = RefLocals(bvh, i);
  if (u > 0 && i + 1 < n) {
    const std::vector<RefLocal> b = RefLocals(bvh, i + 1);
    for (size_t j = 0; j < a.size(); ++j) {
      a[j].rotation = RefQuatToMatrix(RefSlerp(RefMatrixToQuat(a[j].rotation), RefMatrixToQuat(b[j].rotation), u));
      a[j].translation = (1 - u) * a[j].translation + u * b[j].translation;
    }
  }
  return RefWorldPositions(bvh, a);
}

// The engine's world joint positions for a local pose.
inline std::vector<Eigen::Vector3d> EngineWorldPositions(const Skeleton& sk, const std::vector<Trs>& local) {
  std::vector<Eigen::Affine3d> world(sk.size());
  ComputeWorld(sk, local, world);
  std::vector<Eigen::Vector3d> pos(sk.size());
  for (size_t i = 0; i < sk.size(); ++i) pos[i] = world[i].translation();
  return pos;
}

inline std::vector<Eigen::Vector3d> EnginePositionsAt(const BvhData& d, double t) {
  std::vector<Trs> local(d.skeleton->size());
  EXPECT_TRUE(SampleClip(*d.clip, t, {}, local).ok());
  return EngineWorldPositions(*d.skeleton, local);
}

inline BvhData ParseExpectOk(const std::string& text) {
  StatusOr<BvhData> d = ParseBvh(text);
  EXPECT_TRUE(d.ok()) << d.status().message();
  return d.ok() ? *d : BvhData{};
}

inline double MaxDistance(const std::vector<Eigen::Vector3d>& a, const std::vector<Eigen::Vector3d>& b) {
  double d = a.size() == b.size() ? 0.0 : INFINITY;
  for (size_t i = 0; i < a.size() && i < b.size(); ++i) d = std::max(d, (a[i] - b[i]).norm());
  return d;
}

inline std::vector<std::string> RotationChannels(const std::string& order) {
  std::vector<std::string> c;
  for (char a : order) c.push_back(std::string(1, a) + "rotation");
  return c;
}

// A file built in the test: a non-zero root OFFSET, position channels on
// the root (in an unusual order) and interleaved with rotations on a
// non-root joint, joints with 2, 1, 0 and proper-Euler rotation channels.
inline RefBvh MakeTestBvh(const std::string& order, int frames = 12) {
  RefBvh b;
  b.frame_time = 0.05;
  auto add = [&](std::string name, int parent, Eigen::Vector3d offset, std::vector<std::string> channels) {
    RefJoint j;
    j.name = std::move(name);
    j.parent = parent;
    j.offset = offset;
    j.channels = std::move(channels);
    b.joints.push_back(j);
    return static_cast<int>(b.joints.size()) - 1;
  };
  std::vector<std::string> root = {"Yposition", "Xposition", "Zposition"};
  for (auto& c : RotationChannels(order)) root.push_back(c);
  const int hips = add("Hips", -1, {3.5, -2.0, 5.25}, root);
  const auto r = RotationChannels(order);
  const int spine = add("Spine", hips, {0, 10, 1}, {r[0], "Zposition", r[1], "Xposition", r[2]});
  const int head = add("Head", spine, {0.5, 8, -1}, {"Zrotation", "Xrotation"});
  b.joints[static_cast<size_t>(head)].end_site = Eigen::Vector3d(0, 4, 0.5);
  const int arm = add("Arm", spine, {6, 2, 0}, {"Yrotation"});
  const int fixed = add("Fixed", arm, {5, 0, 0}, {});
  const int hand = add("Hand", fixed, {4, -1, 0}, RotationChannels("ZXZ"));
  b.joints[static_cast<size_t>(hand)].end_site = Eigen::Vector3d(2, 0, 0);
  add("Leg", hips, {-2, -9, 0}, r);

  size_t columns = 0;
  for (const auto& j : b.joints) columns += j.channels.size();
  std::mt19937 rng(static_cast<unsigned>(order[0] * 31 + order[1] * 7 + order[2]));
  std::uniform_real_distribution<double> angle(-180, 180), pos(-5, 5);
  for (int f = 0; f < frames; ++f) {
    std::vector<double> row;
    for (const auto& j : b.joints)
      for (const auto& c : j.channels) row.push_back(c.find("rotation") != std::string::npos ? angle(rng) : pos(rng));
    b.frames.push_back(row);
  }
  return b;
}

}  // namespace armature::testing
