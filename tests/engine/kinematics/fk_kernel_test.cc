// ComputeWorld's vector kernels against the scalar loops (bit for bit) and
// against Eigen's own affine and quaternion products (within 1e-12), on
// every frame of every real clip in ../shared/data and on small skeletons
// whose joint counts leave a partial block of four.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <random>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/clip.h"
#include "armature/engine/kinematics/fk.h"
#include "../testing/shared_clips.h"

namespace armature {
namespace {

const std::vector<test_util::SharedClip>& Clips() {
  static const std::vector<test_util::SharedClip> clips = test_util::LoadSharedClips();
  return clips;
}

// The first differing entry of two world poses, bitwise, or -1.
int FirstBitDifference(const std::vector<Eigen::Affine3d>& a, const std::vector<Eigen::Affine3d>& b) {
  for (size_t i = 0; i < a.size(); ++i)
    for (int e = 0; e < 16; ++e)
      if (std::bit_cast<uint64_t>(a[i].matrix().data()[e]) != std::bit_cast<uint64_t>(b[i].matrix().data()[e]))
        return static_cast<int>(16 * i) + e;
  return -1;
}

// The first joint whose world rotations differ, bitwise, or -1.
int FirstBitDifference(const std::vector<Eigen::Quaterniond>& a, const std::vector<Eigen::Quaterniond>& b) {
  for (size_t i = 0; i < a.size(); ++i)
    for (int e = 0; e < 4; ++e)
      if (std::bit_cast<uint64_t>(a[i].coeffs()[e]) != std::bit_cast<uint64_t>(b[i].coeffs()[e]))
        return static_cast<int>(i);
  return -1;
}

// world[i] = world[parent] · local[i].ToAffine(), with Eigen's 4×4 product.
std::vector<Eigen::Affine3d> AffineChain(const Skeleton& s, const std::vector<Trs>& local) {
  std::vector<Eigen::Affine3d> world(s.size());
  for (size_t i = 0; i < s.size(); ++i)
    world[i] = s.parents[i] < 0 ? local[i].ToAffine() : world[static_cast<size_t>(s.parents[i])] * local[i].ToAffine();
  return world;
}

// Every frame of the clip (its key times when it has no frame time), sampled
// as stored; `check` gets each local pose.
template <class Check>
void ForEachFrame(const Clip& clip, Check check) {
  const size_t frames = std::max<size_t>(clip.frame_count, 2);
  std::vector<Trs> local(clip.skeleton->size());
  for (size_t f = 0; f < frames; ++f) {
    const double t = std::min(clip.duration, clip.duration * static_cast<double>(f) / static_cast<double>(frames - 1));
    ASSERT_TRUE(SampleClip(clip, t, {}, local).ok());
    check(t, local);
  }
}

TEST(FkKernel, EveryFrameOfEverySharedClipIsTheScalarLoopsBitForBit) {
  if (Clips().empty()) GTEST_SKIP() << "../shared/data is absent";
  size_t poses = 0;
  for (const test_util::SharedClip& c : Clips()) {
    const Skeleton& s = *c.clip->skeleton;
    std::vector<Eigen::Affine3d> fast(s.size()), scalar(s.size()), with_rotations(s.size());
    std::vector<Eigen::Quaterniond> fast_rotation(s.size()), scalar_rotation(s.size());
    ForEachFrame(*c.clip, [&](double t, const std::vector<Trs>& local) {
      ComputeWorld(s, local, fast);
      ComputeWorld(s, local, with_rotations, fast_rotation);
      ComputeWorldScalar(s, local, scalar, scalar_rotation);
      ASSERT_EQ(FirstBitDifference(fast_rotation, scalar_rotation), -1) << c.name << " at t=" << t;
      ASSERT_EQ(FirstBitDifference(with_rotations, scalar), -1) << c.name << " at t=" << t;
      const int at = FirstBitDifference(fast, scalar);
      ASSERT_EQ(at, -1) << c.name << " at t=" << t << ": joint " << at / 16 << ", entry " << at % 16 << ": "
                        << fast[static_cast<size_t>(at / 16)].matrix().data()[at % 16] << " against "
                        << scalar[static_cast<size_t>(at / 16)].matrix().data()[at % 16];
      ++poses;
    });
  }
  EXPECT_GT(poses, 2752u);  // CMU 01_01's frames alone
}

TEST(FkKernel, EveryFrameOfEverySharedClipIsEigensAffineChain) {
  if (Clips().empty()) GTEST_SKIP() << "../shared/data is absent";
  constexpr double kTolerance = 1e-12;  // of the pose's largest coordinate (and at least 1)
  for (const test_util::SharedClip& c : Clips()) {
    const Skeleton& s = *c.clip->skeleton;
    std::vector<Eigen::Affine3d> world(s.size());
    std::vector<Eigen::Quaterniond> rotation(s.size()), eigen_rotation(s.size());
    double worst = 0, worst_rotation = 0;
    ForEachFrame(*c.clip, [&](double, const std::vector<Trs>& local) {
      ComputeWorld(s, local, world, rotation);
      const std::vector<Eigen::Affine3d> chain = AffineChain(s, local);
      double size = 1;
      for (const Eigen::Affine3d& w : chain) size = std::max(size, w.translation().cwiseAbs().maxCoeff());
      for (size_t i = 0; i < s.size(); ++i) {
        worst = std::max(worst, (world[i].matrix() - chain[i].matrix()).cwiseAbs().maxCoeff() / size);
        const int p = s.parents[i];
        eigen_rotation[i] = p < 0 ? local[i].rotation : eigen_rotation[static_cast<size_t>(p)] * local[i].rotation;
        worst_rotation =
            std::max(worst_rotation, (rotation[i].coeffs() - eigen_rotation[i].coeffs()).cwiseAbs().maxCoeff());
      }
    });
    EXPECT_LE(worst, kTolerance) << c.name;
    EXPECT_LE(worst_rotation, kTolerance) << c.name << ": world rotations against Eigen's quaternion product";
  }
}

// 1 to 11 joints (partial blocks of four), a second root among them, random
// rotations (not normalized: the formula is applied as is), translations
// and scales, negative ones too.
TEST(FkKernel, PartialBlocksSecondRootsAndScalesAreTheScalarLoopsBitForBit) {
  std::mt19937 rng(30);
  std::uniform_real_distribution<double> u(-2, 2);
  for (size_t n = 1; n <= 11; ++n) {
    Skeleton s;
    std::vector<Trs> local(n);
    for (size_t i = 0; i < n; ++i) {
      s.names.push_back("j" + std::to_string(i));
      s.parents.push_back(i == 0 || i == 5 ? -1 : static_cast<int>(rng() % i));
      local[i].translation = {u(rng), u(rng), u(rng)};
      local[i].rotation = Eigen::Quaterniond(u(rng), u(rng), u(rng), u(rng));
      if (i % 2 == 1) local[i].scale = {u(rng), u(rng), u(rng)};
    }
    std::vector<Eigen::Affine3d> fast(n), scalar(n);
    std::vector<Eigen::Quaterniond> fast_rotation(n), scalar_rotation(n);
    ComputeWorld(s, local, fast, fast_rotation);
    ComputeWorldScalar(s, local, scalar, scalar_rotation);
    EXPECT_EQ(FirstBitDifference(fast, scalar), -1) << n << " joints";
    EXPECT_EQ(FirstBitDifference(fast_rotation, scalar_rotation), -1) << n << " joints";
    for (size_t i = 0; i < n; ++i) {
      const int p = s.parents[i];
      const Eigen::Quaterniond eigen =
          p < 0 ? local[i].rotation : scalar_rotation[static_cast<size_t>(p)] * local[i].rotation;
      EXPECT_TRUE(scalar_rotation[i].coeffs().isApprox(eigen.coeffs(), 1e-12)) << n << ": " << i;
    }
    const std::vector<Eigen::Affine3d> chain = AffineChain(s, local);
    for (size_t i = 0; i < n; ++i) EXPECT_TRUE(fast[i].matrix().isApprox(chain[i].matrix(), 1e-12)) << n << ": " << i;
  }
}

}  // namespace
}  // namespace armature
