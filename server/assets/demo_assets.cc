#include "server/assets/demo_assets.h"

#include <chrono>

#include <spdlog/spdlog.h>

#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/demo_character.h"
#include "armature/engine/io/demo_walk.h"

namespace armature::server {

namespace {

// Makes one demo file and imports it through the same path as an upload, so
// it is persisted. Replicas starting together on a new shared data dir all
// try: the first imports it, the others find the name taken, which is fine.
template <class MakeFile>
Status Seed(AssetStore& store, const std::string& name, const std::string& filename, const MakeFile& make) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  StatusOr<std::string> bytes = make();
  if (!bytes.ok()) return bytes.status();
  const auto made = Clock::now();
  ImportRequest request;
  request.name = name;
  request.filename = filename;
  request.bytes = std::move(*bytes);
  const Status st = store.Import(std::move(request)).status();
  if (st.code() == StatusCode::kAlreadyExists) return Status::Ok();
  if (!st.ok()) return st.WithContext("demo asset '" + name + "': ");
  const auto ms = [](auto d) { return std::chrono::duration<double, std::milli>(d).count(); };
  spdlog::info("seeded demo asset '{}' in {:.1f} ms (made in {:.1f} ms, imported in {:.1f} ms)", name,
               ms(Clock::now() - start), ms(made - start), ms(Clock::now() - made));
  return Status::Ok();
}

}  // namespace

Status SeedDemoAssets(AssetStore& store) {
  const Status walk =
      Seed(store, "demo_walk", "demo_walk.bvh", [] { return StatusOr<std::string>(WriteBvh(*MakeDemoWalk().clip)); });
  const Status character = Seed(store, "demo_character", "demo_character.glb", &MakeDemoCharacterGlb);
  return walk.ok() ? character : walk;
}

}  // namespace armature::server
