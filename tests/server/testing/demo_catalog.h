// A catalog built in memory from the engine's demo assets, the way the store
// builds one after an import, for unit tests of each slice's pure handlers.
#pragma once

#include <map>
#include <memory>
#include <string>

#include <gtest/gtest.h>

#include "armature/engine/anim/compression/clip_keys.h"
#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/demo_character.h"
#include "armature/engine/io/demo_walk.h"
#include "server/assets/catalog.h"
#include "server/assets/runtime_clips.h"

namespace armature::server::test_util {

inline std::shared_ptr<const StoredAsset> ParsedAsset(const std::string& name, AssetFormat format,
                                                      const std::string& bytes, const ClipPrecision& precision = {}) {
  auto contents = ParseAsset(format, bytes, name);
  EXPECT_TRUE(contents.ok()) << contents.status().message();
  auto asset = std::make_shared<StoredAsset>();
  asset->record.name = name;
  asset->record.format = format;
  asset->contents = std::move(*contents);
  const Status compressed = CompressClips(asset->contents, precision);  // as the store does
  EXPECT_TRUE(compressed.ok()) << compressed.message();
  return asset;
}

// The keys a stored clip's runtime form holds (ClipKeysOf): the stored keys
// of an exact clip, else its samples at its frames.
inline std::shared_ptr<const Clip> StoredKeys(const NamedClip& clip) {
  auto keys = ClipKeysOf(*clip.runtime);
  EXPECT_TRUE(keys.ok()) << keys.status().message();
  return keys.ok() ? *keys : nullptr;
}

// "demo_character" (mesh demo_character.body, clip demo_character.walk) and
// "demo_walk" (skeleton and clip demo_walk).
// `precision`: the clips' runtime form (exact keeps the parsed keys in NamedClip::clip).
inline std::shared_ptr<const Catalog> DemoCatalog(const ClipPrecision& precision = {}) {
  auto glb = MakeDemoCharacterGlb();
  EXPECT_TRUE(glb.ok()) << glb.status().message();
  std::map<std::string, std::shared_ptr<const StoredAsset>> assets;
  assets["demo_character"] = ParsedAsset("demo_character", AssetFormat::kGlb, *glb, precision);
  assets["demo_walk"] = ParsedAsset("demo_walk", AssetFormat::kBvh, WriteBvh(*MakeDemoWalk().clip), precision);
  auto catalog = BuildCatalog(std::move(assets));
  EXPECT_TRUE(catalog.ok()) << catalog.status().message();
  return std::move(*catalog);
}

}  // namespace armature::server::test_util
