#include "server/assets/bucket/bucket_layout.h"

#include <gtest/gtest.h>

#include <set>

namespace armature::server {
namespace {

TEST(BucketLayout, VersionsSortInTimeOrderAndAreUnique) {
  std::set<std::string> seen;
  std::string previous;
  for (int i = 0; i < 1000; ++i) {
    const std::string v = NewVersion(previous);
    EXPECT_GT(v, previous);
    EXPECT_EQ(v.size(), 23u + 1 + 16) << v;
    EXPECT_TRUE(seen.insert(v).second);
    previous = v;
  }
}

TEST(BucketLayout, ANewVersionSortsAfterOneFromAClockAhead) {
  // A version written by a replica whose clock is a year ahead.
  const std::string ahead = "20991231T235959.999999Z-00000000000000ff";
  const std::string v = NewVersion(ahead);
  EXPECT_GT(v, ahead);
  EXPECT_EQ(v.substr(0, 8), "21000101") << v;
}

TEST(BucketLayout, VersionsByNameFromAListing) {
  const std::string a1 = "20260101T000000.000001Z-0000000000000001", a2 = "20260101T000000.000002Z-0000000000000000";
  std::vector<ObjectEntry> listing = {{"p/versions/arm/" + a2, 10}, {"p/versions/arm/" + a1, 10},
                                      {"p/versions/leg/" + a1, 10}, {"p/versions/junk", 1},
                                      {"p/versions/arm/short", 1},  {"p/objects/arm/" + a1 + "/source.bvh", 5}};
  auto versions = VersionsByName(listing, "p/");
  ASSERT_EQ(versions.size(), 2u);
  EXPECT_EQ(versions["arm"], (std::vector<std::string>{a1, a2}));
  EXPECT_EQ(versions["leg"], (std::vector<std::string>{a1}));
}

TEST(BucketLayout, RecordRoundTripAndTombstone) {
  VersionRecord v;
  v.record.name = "arm";
  v.record.version = NewVersion();
  v.record.format = AssetFormat::kGltf;
  v.record.file = "files/arm." + v.record.version + ".gltf";
  v.record.resources = {{"a.bin", "files/arm.x.res0.a.bin"}};
  v.record.size_bytes = 42;
  v.source = {"objects/arm/" + v.record.version + "/source.gltf", 30, Sha256Hex("x")};
  v.resources = {{"a.bin", {"objects/arm/" + v.record.version + "/res0", 12, Sha256Hex("y")}}};
  auto back = VersionRecordFromJson(VersionRecordToJson(v));
  ASSERT_TRUE(back.ok()) << back.status().message();
  EXPECT_FALSE(back->deleted);
  EXPECT_EQ(back->record.version, v.record.version);
  EXPECT_EQ(back->record.resources, v.record.resources);
  EXPECT_EQ(back->source.sha256, Sha256Hex("x"));
  EXPECT_EQ(back->resources.at("a.bin").size, 12);

  VersionRecord tomb;
  tomb.deleted = true;
  tomb.record.name = "arm";
  tomb.record.version = NewVersion();
  auto gone = VersionRecordFromJson(VersionRecordToJson(tomb));
  ASSERT_TRUE(gone.ok());
  EXPECT_TRUE(gone->deleted);
  // A partial record (a torn write) is refused, never half read.
  const std::string text = VersionRecordToJson(v);
  EXPECT_EQ(VersionRecordFromJson(text.substr(0, text.size() / 2)).status().code(), StatusCode::kInvalidArgument);
}

TEST(BucketLayout, Sha256MatchesTheStandardVector) {
  EXPECT_EQ(Sha256Hex("abc"), "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad");
}

}  // namespace
}  // namespace armature::server
