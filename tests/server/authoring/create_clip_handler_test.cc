// CreateClip over a store in a temporary data dir: keys onto a skeleton,
// merged into the stored clip, baked from a motion; what is stored samples
// as the keys say.
#include "server/authoring/create_clip_handler.h"

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "../testing/temp_store.h"
#include "server/authoring/create_clip_validation.h"

namespace armature::server {
namespace {

using test_util::OpenDemoStore;
using test_util::OpenStore;
using test_util::TempDir;

// A 90° turn about Y at t = 1 of `joint`, from the identity at t = 0.
void AddTurn(v1::CreateClipRequest& request, const std::string& joint) {
  v1::JointKeys* keys = request.add_tracks();
  keys->set_joint(joint);
  keys->add_times(0);
  keys->add_times(1);
  const double s = std::sqrt(0.5);
  for (double v : {1.0, 0.0, 0.0, 0.0, s, 0.0, s, 0.0}) keys->add_rotations(v);
}

// The local rotation of `joint` in the stored clip `clip` at `time`.
Eigen::Quaterniond RotationAt(const Catalog& catalog, const std::string& clip, const std::string& joint, double time) {
  const auto c_keys = test_util::StoredKeys(*catalog.FindClip(clip)->part);
  const Clip& c = *c_keys;
  std::vector<Trs> pose(c.skeleton->size());
  EXPECT_TRUE(SampleClip(c, time, SampleOptions{}, pose).ok());
  return pose[static_cast<size_t>(c.skeleton->Find(joint))].rotation;
}

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) { return a.angularDistance(b); }

TEST(CreateClipHandler, KeysAreStoredAsAClipOfTheSkeletonThatSamplesAsKeyed) {
  TempDir dir;
  auto store = OpenDemoStore(dir.path());
  v1::CreateClipRequest request;
  request.set_name("turn");
  request.set_skeleton("demo_walk");
  AddTurn(request, "Head");
  v1::CreateClipResponse response;
  const Status st = CreateClip(*store, Limits{}, request, &response);
  ASSERT_TRUE(st.ok()) << st.message();
  EXPECT_EQ(response.clip().name(), "turn");
  EXPECT_EQ(response.clip().skeleton(), "demo_walk");
  EXPECT_EQ(response.clip().frames(), 2);
  EXPECT_EQ(response.clip().duration(), 1.0);
  EXPECT_EQ(response.asset().name(), "turn");
  EXPECT_EQ(response.clip().joints_size(),
            static_cast<int>(store->Snapshot()->FindSkeleton("demo_walk")->part->skeleton->size()));
  // Reloaded from the data dir: halfway is 45° about Y (slerp), the other joints at rest.
  auto reopened = OpenStore(dir.path());
  const auto catalog = reopened->Snapshot();
  const Eigen::Quaterniond half(Eigen::AngleAxisd(M_PI / 4, Eigen::Vector3d::UnitY()));
  EXPECT_LT(AngleBetween(RotationAt(*catalog, "turn", "Head", 0.5), half), 1e-5);
  const Skeleton& skeleton = *catalog->FindSkeleton("demo_walk")->part->skeleton;
  const int knee = skeleton.Find("LeftKnee");
  EXPECT_LT(AngleBetween(RotationAt(*catalog, "turn", "LeftKnee", 0.5), skeleton.rest[knee].rotation), 1e-6);
}

TEST(CreateClipHandler, AMergeKeepsTheStoredTracksAndDeletesThoseGivenWithoutTimes) {
  TempDir dir;
  auto store = OpenDemoStore(dir.path());
  v1::CreateClipRequest first;
  first.set_name("turn");
  first.set_skeleton("demo_walk");
  AddTurn(first, "Head");
  v1::CreateClipResponse response;
  ASSERT_TRUE(CreateClip(*store, Limits{}, first, &response).ok());

  v1::CreateClipRequest merge;
  merge.set_name("turn");
  merge.set_merge(true);  // the skeleton: the stored clip's
  AddTurn(merge, "Chest");
  const Status st = CreateClip(*store, Limits{}, merge, &response);
  ASSERT_TRUE(st.ok()) << st.message();
  const Eigen::Quaterniond turned(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()));
  auto catalog = store->Snapshot();
  EXPECT_LT(AngleBetween(RotationAt(*catalog, "turn", "Head", 1), turned), 1e-5);
  EXPECT_LT(AngleBetween(RotationAt(*catalog, "turn", "Chest", 1), turned), 1e-5);

  v1::CreateClipRequest remove;
  remove.set_name("turn");
  remove.set_merge(true);
  remove.add_tracks()->set_joint("Head");
  ASSERT_TRUE(CreateClip(*store, Limits{}, remove, &response).ok());
  catalog = store->Snapshot();
  const Skeleton& skeleton = *catalog->FindSkeleton("demo_walk")->part->skeleton;
  EXPECT_LT(AngleBetween(RotationAt(*catalog, "turn", "Head", 1), skeleton.rest[skeleton.Find("Head")].rotation), 1e-6);
  EXPECT_LT(AngleBetween(RotationAt(*catalog, "turn", "Chest", 1), turned), 1e-5);
}

TEST(CreateClipHandler, CubicKeysWithoutTangentsSampleAsTheEngineSamplesCubic) {
  TempDir dir;
  auto store = OpenDemoStore(dir.path());
  v1::CreateClipRequest request;
  request.set_name("bob");
  request.set_skeleton("demo_walk");
  v1::JointKeys* keys = request.add_tracks();
  keys->set_joint("Hips");
  keys->set_interpolation(v1::CUBIC);
  const std::vector<double> times = {0, 0.5, 1, 1.5};
  const std::vector<double> heights = {90, 96, 88, 93};
  for (size_t k = 0; k < times.size(); ++k) {
    keys->add_times(times[k]);
    for (double v : {0.0, heights[k], 0.0}) keys->add_translations(v);
  }
  v1::CreateClipResponse response;
  const Status st = CreateClip(*store, Limits{}, request, &response);
  ASSERT_TRUE(st.ok()) << st.message();

  // The same keys as an engine clip, CUBIC with no tangents given.
  const auto catalog = store->Snapshot();
  Clip reference;
  reference.skeleton = catalog->FindSkeleton("demo_walk")->part->skeleton;
  reference.joints.resize(reference.skeleton->size());
  Vec3Track& t = reference.joints[0].translation;
  t.times = times;
  for (double h : heights) t.values.emplace_back(0, h, 0);
  t.interpolation = Interpolation::kCubic;
  reference.duration = 1.5;
  reference.frame_count = 4;
  const auto stored_keys = test_util::StoredKeys(*catalog->FindClip("bob")->part);
  const Clip& stored = *stored_keys;
  std::vector<Trs> a(reference.skeleton->size()), b(reference.skeleton->size());
  for (double time : {0.2, 0.7, 1.3}) {
    ASSERT_TRUE(SampleClip(stored, time, SampleOptions{}, a).ok());
    ASSERT_TRUE(SampleClip(reference, time, SampleOptions{}, b).ok());
    EXPECT_NEAR(a[0].translation.y(), b[0].translation.y(), 1e-4) << "at " << time;
  }
  // Not the straight line between the keys: the curve bulges.
  ASSERT_TRUE(SampleClip(stored, 0.25, SampleOptions{}, a).ok());
  EXPECT_GT(std::abs(a[0].translation.y() - 93), 1e-2);
}

TEST(CreateClipHandler, ABakeIsStoredAndItsTracksMayBeDeleted) {
  TempDir dir;
  auto store = OpenDemoStore(dir.path());
  v1::CreateClipRequest request;
  request.set_name("baked");
  request.mutable_bake()->mutable_motion()->add_layers()->set_clip("demo_walk");
  request.mutable_bake()->set_fps(10);
  request.mutable_bake()->set_duration(0.5);
  request.add_tracks()->set_joint("Head");  // no times: the baked Head track goes
  request.set_precision("exact");           // the keys to 1e-5 rad; create_clip_bake_bound_test does the default
  v1::CreateClipResponse response;
  const Status st = CreateClip(*store, Limits{}, request, &response);
  ASSERT_TRUE(st.ok()) << st.message();
  EXPECT_EQ(response.clip().skeleton(), "demo_walk");
  EXPECT_EQ(response.clip().frames(), 6);  // 0, 0.1, …, 0.5
  const auto catalog = store->Snapshot();
  const auto stored_keys = test_util::StoredKeys(*catalog->FindClip("baked")->part);
  const Clip& stored = *stored_keys;
  const int head = stored.skeleton->Find("Head");
  EXPECT_TRUE(stored.joints[static_cast<size_t>(head)].rotation.empty());
  // Another joint's key is the walk at that key's time.
  const double key = StoredKeyTime(0.3);
  EXPECT_LT(
      AngleBetween(RotationAt(*catalog, "baked", "LeftKnee", key), RotationAt(*catalog, "demo_walk", "LeftKnee", key)),
      1e-5);
}

TEST(CreateClipHandler, RequestsThatCannotBeMadeNameTheirField) {
  TempDir dir;
  auto store = OpenDemoStore(dir.path());
  v1::CreateClipResponse response;
  const auto error = [&](const v1::CreateClipRequest& request) {
    return CreateClip(*store, Limits{}, request, &response);
  };
  v1::CreateClipRequest request;
  EXPECT_EQ(error(request).message(), "name: required");
  request.set_name("x");
  AddTurn(request, "Head");
  EXPECT_EQ(error(request).message(), "skeleton: required (the skeleton the clip animates)");
  request.set_merge(true);
  Status st = error(request);
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_EQ(st.message(), "merge: there is no asset 'x' to edit (create it first, without merge)");
  request.set_name("demo_character");  // an asset, but not one CreateClip made
  EXPECT_EQ(error(request).message(),
            "merge: asset 'demo_character' has no clip 'demo_character' (only clips made by CreateClip can be merged "
            "into)");
  request.set_name("demo_walk");  // an imported BVH: its clip is named after it, but CreateClip did not make it
  EXPECT_EQ(error(request).message(),
            "merge: asset 'demo_walk' has no clip 'demo_walk' (only clips made by CreateClip can be merged into)");
  request.set_name("x");
  request.mutable_bake()->mutable_motion()->add_layers()->set_clip("demo_walk");
  EXPECT_EQ(error(request).message(), "bake: not with merge (bake makes every joint's track anew)");
  request.set_merge(false);
  request.mutable_bake()->set_duration(1);
  request.set_skeleton("demo_character");
  EXPECT_EQ(error(request).message(),
            "skeleton: 'demo_character', but bake.motion animates skeleton 'demo_walk' (leave skeleton out or name "
            "that one)");
  v1::CreateClipRequest no_keys;
  no_keys.set_name("x");
  no_keys.set_skeleton("demo_walk");
  st = error(no_keys);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(), "tracks: the clip would have no keys (give at least one track with times)");
  EXPECT_FALSE(store->Snapshot()->assets.contains("x"));
}

}  // namespace
}  // namespace armature::server
