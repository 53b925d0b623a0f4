// Replicas without a shared disk: real servers on one bucket of a real
// S3-compatible server (s3rver), each with its own cache dir.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <thread>

#include <regex>

#include "store/store_fixture.h"

namespace armature::testing {
namespace {

// The keys of `bucket`, listed by plain HTTP (s3rver lists anonymous
// requests), not by the server's client: an independent look.
std::vector<std::string> KeysOf(const S3rverProcess& s3, const std::string& bucket) {
  const std::string xml =
      HttpGet("http://127.0.0.1:" + std::to_string(s3.port()) + "/" + bucket + "?list-type=2&max-keys=1000").body;
  EXPECT_EQ(xml.find("<IsTruncated>true"), std::string::npos);
  std::vector<std::string> keys;
  const std::regex key("<Key>([^<]*)</Key>");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), key); it != std::sregex_iterator(); ++it)
    keys.push_back((*it)[1]);
  return keys;
}

TEST_F(StoreTest, AnImportOnOneReplicaIsServedByTheOtherWithinTwoSeconds) {
  S3rverProcess s3({"armature.assets.test"});  // a bucket name with dots
  const std::string url = s3.Url("armature.assets.test", "replicas");
  auto a = Replica(url), b = Replica(url);
  client::Client ca(OptionsFor(*a)), cb(OptionsFor(*b));
  std::vector<double> delays;
  for (int i = 0; i < 3; ++i) {
    const std::string name = "arm" + std::to_string(i);
    const auto imported = ca.Import({name + ".bvh", kArmBvh});
    const auto t0 = std::chrono::steady_clock::now();
    ASSERT_TRUE(WaitFor([&] { return CodeOf([&] { cb.GetClip(name); }) == grpc::StatusCode::OK; }, 30))
        << ReadFile(b->log_file());
    delays.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    // B serves the very version A wrote, and evaluates it as A does.
    EXPECT_FALSE(imported.asset().version().empty());
    EXPECT_EQ(cb.GetAsset(name).version(), imported.asset().version());
  }
  std::sort(delays.begin(), delays.end());
  std::cout << "replica-to-replica delays (s, 1 s poll): " << delays[0] << " " << delays[1] << " " << delays[2] << "\n";
  EXPECT_LT(delays[1], 2.0);  // the median: a loaded machine may stall one
  v1::EvaluateClipRequest r;
  r.set_clip("arm0");
  r.add_times(0.25);
  r.set_space(v1::WORLD);
  const auto pb = cb.EvaluateClip(r);
  EXPECT_NEAR(pb.poses(0).translations(4), 2 + 2 * std::sin(M_PI / 4), 1e-4);  // the default clip bound, in metres
}

TEST_F(StoreTest, ConcurrentImportsOnTwoReplicasKeepEveryOne) {
  S3rverProcess s3({"bucket"});
  auto a = Replica(s3.Url("bucket"), 200), b = Replica(s3.Url("bucket"), 200);
  constexpr int kEach = 8;
  auto import_all = [&](const ServerProcess& server, const std::string& prefix) {
    client::Client client(OptionsFor(server));
    for (int i = 0; i < kEach; ++i)
      EXPECT_EQ(MessageOf([&] { client.Import({prefix + std::to_string(i) + ".bvh", kArmBvh}); }), "");
  };
  std::thread ta([&] { import_all(*a, "a"); }), tb([&] { import_all(*b, "b"); });
  ta.join();
  tb.join();
  client::Client ca(OptionsFor(*a)), cb(OptionsFor(*b));
  EXPECT_TRUE(WaitFor([&] { return AssetNames(ca).size() == 2 * kEach && AssetNames(cb).size() == 2 * kEach; }, 30));
  EXPECT_EQ(VersionsOf(ca), VersionsOf(cb));
}

TEST_F(StoreTest, AReplaceIsANewVersionSwappedInAndOldOnesPruned) {
  S3rverProcess s3({"bucket"});
  auto a = Replica(s3.Url("bucket"), 200, {"--store-keep-versions", "2"});
  auto b = Replica(s3.Url("bucket"), 200);
  client::Client ca(OptionsFor(*a)), cb(OptionsFor(*b));
  std::vector<std::string> versions;
  for (int frames : {3, 5, 7, 9}) {
    versions.push_back(ca.Import({"arm.bvh", ArmBvhWithFrames(frames)}, "", "", true).asset().version());
    EXPECT_TRUE(WaitFor(
        [&] {
          return CodeOf([&] { cb.GetClip("arm"); }) == grpc::StatusCode::OK && cb.GetClip("arm").frames() == frames;
        },
        30))
        << frames;
  }
  EXPECT_TRUE(std::is_sorted(versions.begin(), versions.end()));
  EXPECT_EQ(cb.GetAsset("arm").version(), versions.back());
  // --store-keep-versions 2: the two newest records and their files stay, the rest is gone.
  int records = 0, sources = 0;
  for (const std::string& key : KeysOf(s3, "bucket")) {
    records += key.starts_with("versions/arm/");
    sources += key.starts_with("objects/arm/");
    if (key.starts_with("versions/arm/")) {
      EXPECT_TRUE(key.ends_with(versions[2]) || key.ends_with(versions[3])) << key;
    }
  }
  EXPECT_EQ(records, 2);
  EXPECT_EQ(sources, 2);
}

TEST_F(StoreTest, PrefixesWithAndWithoutSlashes) {
  S3rverProcess s3({"bucket"});
  // "", "/" and "//" are all the bucket's root: replicas on each see one another's imports.
  const std::string bucket = "s3://127.0.0.1:" + std::to_string(s3.port()) + "/bucket";
  auto root = Replica(bucket, 200), slash = Replica(bucket + "/", 200), two = Replica(bucket + "//", 200);
  auto nested = Replica(s3.Url("bucket", "a/b"), 200);
  client::Client c_root(OptionsFor(*root)), c_slash(OptionsFor(*slash)), c_two(OptionsFor(*two)),
      c_nested(OptionsFor(*nested));
  c_two.Import({"rooted.bvh", kArmBvh});
  c_nested.Import({"nested.bvh", kArmBvh});
  EXPECT_TRUE(WaitFor([&] { return AssetNames(c_root) == std::set<std::string>{"rooted"}; }, 30));
  EXPECT_TRUE(WaitFor([&] { return AssetNames(c_slash) == std::set<std::string>{"rooted"}; }, 30));
  EXPECT_TRUE(WaitFor([&] { return AssetNames(c_nested) == std::set<std::string>{"nested"}; }, 30));
  std::this_thread::sleep_for(std::chrono::milliseconds(600));  // three polls: "a/b" stays apart from the root
  EXPECT_EQ(AssetNames(c_root), std::set<std::string>{"rooted"});
  EXPECT_EQ(AssetNames(c_nested), std::set<std::string>{"nested"});
  int at_root = 0, under_ab = 0;
  for (const std::string& key : KeysOf(s3, "bucket")) {
    EXPECT_FALSE(key.starts_with("/")) << key;
    EXPECT_EQ(key.find("//"), std::string::npos) << key;
    at_root += key.starts_with("versions/rooted/");
    under_ab += key.starts_with("a/b/versions/nested/");
  }
  EXPECT_EQ(at_root, 1);
  EXPECT_EQ(under_ab, 1);
}

TEST_F(StoreTest, AnImportRacingADeleteOfTheSameNameOnTwoReplicasEndsTheSameOnBoth) {
  S3rverProcess s3({"bucket"});
  auto a = Replica(s3.Url("bucket"), 100), b = Replica(s3.Url("bucket"), 100);
  client::Client ca(OptionsFor(*a)), cb(OptionsFor(*b));
  int kept = 0, deleted = 0;
  for (int round = 0; round < 6; ++round) {
    ca.Import({"race.bvh", kArmBvh}, "", "", true);
    ASSERT_TRUE(WaitFor([&] { return CodeOf([&] { cb.GetAsset("race"); }) == grpc::StatusCode::OK; }, 30));
    std::thread del([&] { (void)CodeOf([&] { ca.DeleteAsset("race"); }); });
    std::thread imp([&] { (void)CodeOf([&] { cb.Import({"race.bvh", ArmBvhWithFrames(5)}, "", "", true); }); });
    del.join();
    imp.join();
    // Both settle on the latest version record: the import (5 frames) or the tombstone.
    std::map<std::string, std::string> va, vb;
    EXPECT_TRUE(WaitFor(
        [&] {
          va = VersionsOf(ca);
          vb = VersionsOf(cb);
          return va == vb;
        },
        30))
        << "round " << round;
    if (va.contains("race")) {
      ++kept;
      EXPECT_EQ(ca.GetClip("race").frames(), 5);
      EXPECT_EQ(cb.GetClip("race").frames(), 5);
    } else {
      ++deleted;
    }
  }
  std::cout << "import won " << kept << ", delete won " << deleted << " of 6 rounds\n";
}

}  // namespace
}  // namespace armature::testing
