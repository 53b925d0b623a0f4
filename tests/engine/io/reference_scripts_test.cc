// Checks the Python references in tests/reference (used by the CLI
// integration tests) against the engine, so both sides vouch for each other.
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <optional>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "armature/engine/io/demo_walk.h"
#include "../testing/bvh_reference.h"
#include "../testing/test_files.h"

namespace armature {
namespace {

const std::string kPython = "/usr/bin/python3";
const std::string kScripts = std::string(ARMATURE_TEST_DIR) + "/reference/";

using test_util::RunCommand;

class ReferenceScripts : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!RunCommand(kPython + " -c 'import numpy, scipy.spatial.transform' 2>/dev/null"))
      GTEST_SKIP() << kPython << " with numpy and scipy is not available";
    dir_ = std::filesystem::temp_directory_path() / ("armature_reference_" + std::to_string(getpid()));
    std::filesystem::create_directories(dir_);
  }
  void TearDown() override {
    if (!dir_.empty()) std::filesystem::remove_all(dir_);
  }

  std::string Write(const std::string& name, const std::string& text) {
    const std::string path = (dir_ / name).string();
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }

  // bvh_fk.py's positions [time][joint], checked for names and times.
  std::vector<std::vector<Eigen::Vector3d>> PythonFk(const std::string& file, const std::vector<double>& times,
                                                     const Skeleton& expect_joints) {
    std::string cmd = kPython + " " + kScripts + "bvh_fk.py " + file;
    for (double t : times) cmd += " " + std::to_string(t);
    const std::optional<std::string> out = RunCommand(cmd);
    EXPECT_TRUE(out.has_value()) << cmd;
    if (!out) return {};
    const nlohmann::json j = nlohmann::json::parse(*out);
    EXPECT_EQ(j["joints"].get<std::vector<std::string>>(), expect_joints.names);
    EXPECT_EQ(j["times"].size(), times.size());
    std::vector<std::vector<Eigen::Vector3d>> result;
    for (const auto& at_time : j["positions"]) {
      std::vector<Eigen::Vector3d> row;
      for (const auto& p : at_time) row.emplace_back(p[0].get<double>(), p[1].get<double>(), p[2].get<double>());
      result.push_back(row);
    }
    return result;
  }

  // Engine and bvh_fk.py agree on `file` at `times` (std::to_string keeps
  // six decimals, so the engine samples the very times the script got).
  void ExpectFkAgrees(const std::string& file, const std::vector<double>& times, double tolerance) {
    const auto text = test_util::ReadFileBytes(file);
    ASSERT_TRUE(text);
    const BvhData d = testing::ParseExpectOk(*text);
    ASSERT_TRUE(d.clip);
    const auto python = PythonFk(file, times, *d.skeleton);
    ASSERT_EQ(python.size(), times.size());
    for (size_t i = 0; i < times.size(); ++i) {
      const double t = std::stod(std::to_string(times[i]));
      EXPECT_LT(testing::MaxDistance(testing::EnginePositionsAt(d, t), python[i]), tolerance) << file << " t=" << t;
    }
  }

  // bvh_reorder.py's output parses to the same motion as its input.
  void ExpectReorderKeepsMotion(const std::string& in, const std::string& order, const std::string& root_offset) {
    const std::string out = (dir_ / ("reordered_" + order + ".bvh")).string();
    ASSERT_TRUE(RunCommand(kPython + " " + kScripts + "bvh_reorder.py " + in + " " + out + " --order " + order +
                           " --root-offset=" + root_offset));
    const BvhData a = testing::ParseExpectOk(*test_util::ReadFileBytes(in));
    const BvhData b = testing::ParseExpectOk(*test_util::ReadFileBytes(out));
    ASSERT_TRUE(a.clip && b.clip);
    EXPECT_EQ(b.skeleton->names, a.skeleton->names);
    EXPECT_NE(b.skeleton->rest[0].translation, a.skeleton->rest[0].translation);
    for (size_t j = 0; j < b.skeleton->size(); ++j) {
      std::string rotations;
      for (Channel c : b.skeleton->channels[j])
        if (IsRotationChannel(c)) rotations += ChannelName(c)[0];
      if (!rotations.empty()) EXPECT_EQ(rotations, order) << b.skeleton->names[j];
    }
    const size_t frames = a.clip->frame_count;
    for (size_t f = 0; f < frames; f += std::max<size_t>(1, frames / 97)) {
      const double t = f * a.clip->frame_time;
      EXPECT_LT(testing::MaxDistance(testing::EnginePositionsAt(a, t), testing::EnginePositionsAt(b, t)), 1e-4)
          << order << " frame " << f;
    }
  }

  std::filesystem::path dir_;
};

TEST_F(ReferenceScripts, FkAgreesWithEngineOnGeneratedFiles) {
  for (const std::string order : {"XZY", "YXZ", "ZYX"}) {
    const std::string file = Write("gen_" + order + ".bvh", testing::WriteRefBvh(testing::MakeTestBvh(order)));
    ExpectFkAgrees(file, {0.0, 0.05, 0.123, 0.31, 0.55}, 1e-9);
  }
  ExpectFkAgrees(Write("walk.bvh", WriteBvh(*MakeDemoWalk().clip)), {0.0, 0.5, 1.01, 2.345, 3.0}, 1e-9);
}

TEST_F(ReferenceScripts, FkAgreesWithEngineOnCmu) {
  const std::string file = test_util::SharedData("bvh/cmu_01_01.bvh").string();
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "shared data " << file << " is absent";
  ExpectFkAgrees(file, {0.0, 0.5004, 11.1, 17.777777, 22.925}, 1e-6);
}

TEST_F(ReferenceScripts, ReorderKeepsTheMotionOfGeneratedFiles) {
  const std::string file = Write("gen.bvh", testing::WriteRefBvh(testing::MakeTestBvh("ZXY", 40)));
  ExpectReorderKeepsMotion(file, "XZY", "1,2,3");
  ExpectReorderKeepsMotion(file, "YZX", "-4,0.5,9");
}

TEST_F(ReferenceScripts, ReorderKeepsTheMotionOfCmu) {
  const std::string file = test_util::SharedData("bvh/cmu_01_01.bvh").string();
  if (!std::filesystem::exists(file)) GTEST_SKIP() << "shared data " << file << " is absent";
  ExpectReorderKeepsMotion(file, "XZY", "4,-3,7");
  ExpectReorderKeepsMotion(file, "YXZ", "-10,2.5,0");
}

}  // namespace
}  // namespace armature
