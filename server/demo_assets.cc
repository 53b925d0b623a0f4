#include "server/demo_assets.h"

#include "armature/engine/bvh.h"
#include "armature/engine/demo_walk.h"

namespace armature::server {

Status SeedDemoAssets(AssetStore& store) {
  // Imported through the same path as an upload: a BVH file, persisted.
  ImportRequest walk;
  walk.name = "demo_walk";
  walk.filename = "demo_walk.bvh";
  walk.bytes = WriteBvh(*MakeDemoWalk().clip);
  return store.Import(std::move(walk)).status();
}

}  // namespace armature::server
