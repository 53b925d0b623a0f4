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
  const Status st = store.Import(std::move(walk)).status();
  // Replicas starting together on a new shared data dir: one of them seeds it.
  return st.code() == StatusCode::kAlreadyExists ? Status::Ok() : st;
}

}  // namespace armature::server
