// A suite whose tests share one real armature-server, started before its first test.
#pragma once

#include <gtest/gtest.h>

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

}  // namespace armature::testing
