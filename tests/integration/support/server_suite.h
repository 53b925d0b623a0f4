// A suite whose tests share one real armature-server, started before its first test.
#pragma once

#include <gtest/gtest.h>

#include "armature/client.h"
#include "support/client_helpers.h"
#include "support/server_process.h"

namespace armature::testing {

class ServerSuite : public ::testing::Test {
 protected:
  // A suite that imports assets defines its own SetUpTestSuite, calling this one first.
  static void SetUpTestSuite() {
    data_ = new TempDir;
    server_ = new ServerProcess(data_->path());
  }
  static void TearDownTestSuite() {
    delete server_;
    delete data_;
    server_ = nullptr;
    data_ = nullptr;
  }

  static inline TempDir* data_ = nullptr;
  static inline ServerProcess* server_ = nullptr;
};

// A suite on CMU 01_01 ("cmu") and RobotExpressive ("robot") from
// ../shared/data, imported once; its tests skip when the files are absent.
class CmuAndRobotSuite : public ServerSuite {
 protected:
  static void SetUpTestSuite() {
    if (SharedData("bvh/cmu_01_01.bvh").empty() || SharedData("gltf/RobotExpressive/RobotExpressive.glb").empty())
      return;
    ServerSuite::SetUpTestSuite();
    client::Client client(OptionsFor(*server_));
    client.ImportFile(SharedData("bvh/cmu_01_01.bvh"), "cmu");
    client.ImportFile(SharedData("gltf/RobotExpressive/RobotExpressive.glb"), "robot");
  }
  void SetUp() override {
    if (!server_) GTEST_SKIP() << "../shared/data (cmu_01_01.bvh, RobotExpressive.glb) is absent";
  }
};

}  // namespace armature::testing
