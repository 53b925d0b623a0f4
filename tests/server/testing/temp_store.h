// An AssetStore over a fresh temporary data dir, for unit tests of what the
// store persists and of the handlers that store what they make (authoring).
#pragma once

#include <stdlib.h>

#include <chrono>
#include <filesystem>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "server/assets/asset_store.h"
#include "server/assets/demo_assets.h"

namespace armature::server::test_util {

// A directory under the system's temp dir, removed with everything in it.
class TempDir {
 public:
  TempDir() {
    std::string pattern = (std::filesystem::temp_directory_path() / "armature-unit-XXXXXX").string();
    EXPECT_NE(::mkdtemp(pattern.data()), nullptr);
    path_ = pattern;
  }
  ~TempDir() {
    std::error_code ec;
    std::filesystem::remove_all(path_, ec);
  }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

// A store on `dir` that never watches the manifest (watch_interval 0), so a
// test sees other stores' writes only when it opens a new store.
inline std::unique_ptr<AssetStore> OpenStore(const std::filesystem::path& dir, Limits limits = {}) {
  StoreOptions options;
  options.limits = limits;
  options.watch_interval = std::chrono::milliseconds(0);
  auto store = AssetStore::Open(dir, options);
  EXPECT_TRUE(store.ok()) << store.status().message();
  return store.ok() ? std::move(*store) : nullptr;
}

// OpenStore with the demo assets imported as a first start seeds them:
// "demo_walk" (BVH) and "demo_character" (glb).
inline std::unique_ptr<AssetStore> OpenDemoStore(const std::filesystem::path& dir, Limits limits = {}) {
  auto store = OpenStore(dir, limits);
  if (store) {
    const Status seeded = SeedDemoAssets(*store);
    EXPECT_TRUE(seeded.ok()) << seeded.message();
  }
  return store;
}

}  // namespace armature::server::test_util
