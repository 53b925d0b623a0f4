// The store over a temporary data dir: what an import, replace and delete
// leave on disk, and what a new store on the same directory loads back.
#include "server/assets/asset_store.h"

#include <gtest/gtest.h>

#include <fstream>
#include <set>

#include "../testing/temp_store.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/demo_walk.h"

namespace armature::server {
namespace {

namespace fs = std::filesystem;
using test_util::OpenStore;
using test_util::TempDir;

ImportRequest WalkImport(const std::string& name, size_t frames = 0) {
  BvhData walk = MakeDemoWalk();
  if (frames > 0) {  // a shorter walk: a second, distinguishable version
    auto clip = std::make_shared<Clip>(*walk.clip);
    for (JointTrack& t : clip->joints)
      for (auto* track : {&t.translation.times, &t.rotation.times})
        if (track->size() > frames) track->resize(frames);
    for (JointTrack& t : clip->joints) {
      if (t.translation.values.size() > frames) t.translation.values.resize(frames);
      if (t.rotation.values.size() > frames) t.rotation.values.resize(frames);
    }
    clip->frame_count = frames;
    clip->duration = static_cast<double>(frames - 1) * clip->frame_time;
    walk.clip = clip;
  }
  ImportRequest request;
  request.name = name;
  request.filename = name + ".bvh";
  request.bytes = WriteBvh(*walk.clip);
  return request;
}

std::set<std::string> FilesIn(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir / "files")) names.insert(entry.path().filename().string());
  return names;
}

TEST(AssetStore, AnImportIsPersistedAndLoadedByANewStoreOnTheSameDir) {
  TempDir dir;
  size_t frames = 0;
  std::string file;
  {
    auto store = OpenStore(dir.path());
    EXPECT_TRUE(store->fresh());
    auto stored = store->Import(WalkImport("walk"));
    ASSERT_TRUE(stored.ok()) << stored.status().message();
    file = (*stored)->record.file;
    EXPECT_TRUE(fs::exists(dir.path() / file));
    EXPECT_EQ((*stored)->record.format, AssetFormat::kBvh);
    EXPECT_EQ((*stored)->record.size_bytes, static_cast<int64_t>(fs::file_size(dir.path() / file)));
    frames = store->Snapshot()->FindClip("walk")->part->runtime->source_frame_count;
  }
  auto reopened = OpenStore(dir.path());
  EXPECT_FALSE(reopened->fresh());
  auto clip = reopened->Snapshot()->FindClip("walk");
  ASSERT_TRUE(clip.ok()) << clip.status().message();
  EXPECT_EQ(clip->part->runtime->source_frame_count, frames);
  EXPECT_EQ(frames, MakeDemoWalk().clip->frame_count);
  EXPECT_EQ(clip->asset->record.file, file);
  EXPECT_TRUE(reopened->Snapshot()->FindSkeleton("walk").ok());
}

TEST(AssetStore, ATakenNameIsAlreadyExistsUnlessReplaceWhichSwapsTheFile) {
  TempDir dir;
  auto store = OpenStore(dir.path());
  auto first = store->Import(WalkImport("walk"));
  ASSERT_TRUE(first.ok()) << first.status().message();
  const Status taken = store->Import(WalkImport("walk", 10)).status();
  EXPECT_EQ(taken.code(), StatusCode::kAlreadyExists);
  EXPECT_EQ(taken.message(), "asset 'walk' already exists (set replace to overwrite it)");

  ImportRequest replace = WalkImport("walk", 10);
  replace.replace = true;
  auto second = store->Import(std::move(replace));
  ASSERT_TRUE(second.ok()) << second.status().message();
  EXPECT_EQ(store->Snapshot()->FindClip("walk")->part->runtime->source_frame_count, 10u);
  // The replaced file is gone; only the new one is stored.
  EXPECT_FALSE(fs::exists(dir.path() / (*first)->record.file));
  EXPECT_EQ(FilesIn(dir.path()), std::set<std::string>{fs::path((*second)->record.file).filename().string()});
  EXPECT_EQ(OpenStore(dir.path())->Snapshot()->FindClip("walk")->part->runtime->source_frame_count, 10u);
}

TEST(AssetStore, ReplaceOnlyOverAnotherVersionIsAborted) {
  TempDir dir;
  auto store = OpenStore(dir.path());
  auto read = store->Import(WalkImport("walk"));
  ASSERT_TRUE(read.ok());
  ImportRequest newer = WalkImport("walk", 12);
  newer.replace = true;
  ASSERT_TRUE(store->Import(std::move(newer)).ok());
  ImportRequest edit = WalkImport("walk", 8);
  edit.replace = true;
  edit.replace_only = *read;  // made from the version that is no longer stored
  const Status st = store->Import(std::move(edit)).status();
  EXPECT_EQ(st.code(), StatusCode::kAborted);
  EXPECT_EQ(st.message(), "asset 'walk' changed while this edit was made from it");
  EXPECT_EQ(store->Snapshot()->FindClip("walk")->part->runtime->source_frame_count, 12u);
}

TEST(AssetStore, DeleteRemovesTheEntryAndItsFileForGood) {
  TempDir dir;
  {
    auto store = OpenStore(dir.path());
    ASSERT_TRUE(store->Import(WalkImport("walk")).ok());
    ASSERT_TRUE(store->Import(WalkImport("keep", 5)).ok());
    auto gone = store->Delete("walk");
    ASSERT_TRUE(gone.ok()) << gone.status().message();
    EXPECT_EQ((*gone)->record.name, "walk");
    EXPECT_FALSE(fs::exists(dir.path() / (*gone)->record.file));
    EXPECT_EQ(store->Snapshot()->FindClip("walk").status().code(), StatusCode::kNotFound);
    EXPECT_EQ(store->Delete("walk").status().code(), StatusCode::kNotFound);
  }
  auto reopened = OpenStore(dir.path());
  EXPECT_EQ(reopened->Snapshot()->assets.size(), 1u);
  EXPECT_TRUE(reopened->Snapshot()->assets.contains("keep"));
  EXPECT_EQ(FilesIn(dir.path()).size(), 1u);
}

TEST(AssetStore, BadRequestsAreInvalidArgumentNamingTheField) {
  TempDir dir;
  auto store = OpenStore(dir.path());
  ImportRequest slash = WalkImport("a/b");
  EXPECT_EQ(store->Import(std::move(slash)).status().message(),
            "name: 'a/b' may only use letters, digits, '.', '_' and '-' (no '/', no NUL)");
  ImportRequest empty = WalkImport("empty");
  empty.bytes.clear();
  const Status st = store->Import(std::move(empty)).status();
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(), "data: the file is empty");
  // No name: the filename's stem.
  ImportRequest unnamed = WalkImport("");
  unnamed.filename = "dir/stride.v2.bvh";
  auto stored = store->Import(std::move(unnamed));
  ASSERT_TRUE(stored.ok()) << stored.status().message();
  EXPECT_EQ((*stored)->record.name, "stride.v2");
  EXPECT_EQ(FilesIn(dir.path()).size(), 1u);
}

TEST(AssetStore, AnImportOverMaxAssetsMbIsRefusedAndLeavesNothing) {
  TempDir dir;
  Limits limits;
  limits.max_assets_bytes = 1;  // 1 byte: any asset is over it
  auto store = OpenStore(dir.path(), limits);
  const Status st = store->Import(WalkImport("walk")).status();
  EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
  EXPECT_NE(st.message().find("--max-assets-mb"), std::string::npos) << st.message();
  EXPECT_TRUE(st.message().starts_with("walk.bvh: ")) << st.message();
  EXPECT_TRUE(FilesIn(dir.path()).empty());
  EXPECT_TRUE(store->Snapshot()->assets.empty());
}

TEST(AssetStore, LeftoversOfAnInterruptedWriteAreRemovedAtOpen) {
  TempDir dir;
  {
    auto store = OpenStore(dir.path());
    ASSERT_TRUE(store->Import(WalkImport("walk")).ok());
  }
  std::ofstream(dir.path() / "files" / "orphan.bvh") << "HIERARCHY";
  std::ofstream(dir.path() / ".manifest.json.tmp-1234") << "{";
  auto reopened = OpenStore(dir.path());
  EXPECT_FALSE(fs::exists(dir.path() / "files" / "orphan.bvh"));
  EXPECT_FALSE(fs::exists(dir.path() / ".manifest.json.tmp-1234"));
  EXPECT_TRUE(reopened->Snapshot()->assets.contains("walk"));
}

TEST(AssetStore, AStoreThatWatchesSeesAnotherStoresImport) {
  TempDir dir;
  StoreOptions watching;
  watching.watch_interval = std::chrono::milliseconds(10);
  auto replica = AssetStore::Open(dir.path(), watching);
  ASSERT_TRUE(replica.ok());
  auto writer = OpenStore(dir.path());
  ASSERT_TRUE(writer->Import(WalkImport("walk")).ok());
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!(*replica)->Snapshot()->assets.contains("walk") && std::chrono::steady_clock::now() < deadline)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_TRUE((*replica)->Snapshot()->FindClip("walk").ok());
}

TEST(AssetStore, AssetNamesAreFileNames) {
  EXPECT_TRUE(ValidateAssetName("fox.Walk-2_b").ok());
  EXPECT_EQ(ValidateAssetName("").message(), "name: must not be empty");
  EXPECT_EQ(ValidateAssetName(".hidden").message(), "name: must not start with '.'");
  EXPECT_TRUE(ValidateAssetName(std::string(128, 'a')).ok());
  EXPECT_EQ(ValidateAssetName(std::string(129, 'a')).message(), "name: longer than 128 characters");
  EXPECT_EQ(ValidateAssetName(std::string("a\0b", 3)).code(), StatusCode::kInvalidArgument);
}

}  // namespace
}  // namespace armature::server
