// RetargetClip over a store in a temporary data dir: the map it reports, the
// clip it stores, and onto a skeleton like the source's own, the same motion.
#include "server/authoring/retarget_handler.h"

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "../testing/temp_store.h"

namespace armature::server {
namespace {

using test_util::OpenDemoStore;
using test_util::TempDir;

v1::RetargetClipRequest Request(const std::string& clip, const std::string& skeleton) {
  v1::RetargetClipRequest request;
  request.set_clip(clip);
  request.set_skeleton(skeleton);
  return request;
}

// The demo character's skeleton is the demo walk's (same names, hierarchy
// and rest, demo_character.h): every joint maps onto its namesake and the
// retargeted walk moves as the source does.
TEST(RetargetHandler, OntoAnIdenticalSkeletonEveryJointMapsAndTheMotionIsKept) {
  TempDir dir;
  auto store = OpenDemoStore(dir.path());
  v1::RetargetClipResponse response;
  const Status st = RetargetClip(*store, Limits{}, Request("demo_character.walk", "demo_walk"), &response);
  ASSERT_TRUE(st.ok()) << st.message();
  const auto catalog = store->Snapshot();
  const Skeleton& target = *catalog->FindSkeleton("demo_walk")->part->skeleton;
  ASSERT_EQ(response.mapping_size(), static_cast<int>(target.size()));
  for (const v1::JointPair& pair : response.mapping()) EXPECT_EQ(pair.source(), pair.target());
  EXPECT_EQ(response.unmapped().source_size(), 0);
  EXPECT_EQ(response.unmapped().target_size(), 0);
  // Named after clip and skeleton, dots made underscores; a clip of the target.
  EXPECT_EQ(response.clip().name(), "demo_character_walk_on_demo_walk");
  EXPECT_EQ(response.clip().skeleton(), "demo_walk");
  EXPECT_EQ(response.asset().name(), "demo_character_walk_on_demo_walk");

  const auto source_keys = test_util::StoredKeys(*catalog->FindClip("demo_character.walk")->part);
  const Clip& source = *source_keys;
  const auto result_keys = test_util::StoredKeys(*catalog->FindClip("demo_character_walk_on_demo_walk")->part);
  const Clip& result = *result_keys;
  std::vector<Trs> a(target.size()), b(target.size());
  for (double t : {0.0, 0.4, 1.3}) {
    ASSERT_TRUE(SampleClip(source, t, SampleOptions{}, a).ok());
    ASSERT_TRUE(SampleClip(result, t, SampleOptions{}, b).ok());
    for (size_t j = 0; j < target.size(); ++j) {
      // The result is compressed again under the default bound, 0.01 cm at 3 cm: a joint's local
      // rotation may move up to about 0.01 / 3 rad where no child lengthens its lever.
      EXPECT_LT(a[j].rotation.angularDistance(b[j].rotation), 0.01 / 3) << target.names[j] << " at " << t;
      EXPECT_LT((a[j].translation - b[j].translation).norm(), 1e-2) << target.names[j] << " at " << t;
    }
  }
}

TEST(RetargetHandler, AnExplicitPairReplacesTheAutomaticOne) {
  TempDir dir;
  auto store = OpenDemoStore(dir.path());
  v1::RetargetClipRequest request = Request("demo_walk", "demo_character");
  request.set_name("swapped");
  v1::JointPair* pair = request.add_map();
  pair->set_source("LeftKnee");
  pair->set_target("RightKnee");
  v1::RetargetClipResponse response;
  const Status st = RetargetClip(*store, Limits{}, request, &response);
  ASSERT_TRUE(st.ok()) << st.message();
  EXPECT_EQ(response.clip().name(), "swapped");
  bool found = false;
  for (const v1::JointPair& p : response.mapping()) {
    if (p.target() == "RightKnee") {
      EXPECT_EQ(p.source(), "LeftKnee");
      found = true;
    }
  }
  EXPECT_TRUE(found);
}

TEST(RetargetHandler, MissingOrUnknownNamesAreRefusedAndNothingIsStored) {
  TempDir dir;
  auto store = OpenDemoStore(dir.path());
  v1::RetargetClipResponse response;
  Status st = RetargetClip(*store, Limits{}, Request("", "demo_walk"), &response);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(), "clip is required (the source clip's name)");
  st = RetargetClip(*store, Limits{}, Request("demo_walk", ""), &response);
  EXPECT_EQ(st.message(), "skeleton is required (the target skeleton's name)");
  st = RetargetClip(*store, Limits{}, Request("Wave", "demo_walk"), &response);
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("'Wave'"), std::string::npos) << st.message();
  st = RetargetClip(*store, Limits{}, Request("demo_walk", "Robot"), &response);
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("'Robot'"), std::string::npos) << st.message();
  v1::RetargetClipRequest bad_pair = Request("demo_walk", "demo_character");
  bad_pair.add_map()->set_source("Tail");
  bad_pair.mutable_map(0)->set_target("Head");
  st = RetargetClip(*store, Limits{}, bad_pair, &response);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_NE(st.message().find("map[0]"), std::string::npos) << st.message();
  EXPECT_EQ(store->Snapshot()->assets.size(), 2u);  // the demo assets only
}

TEST(RetargetHandler, ATakenNameIsAlreadyExistsUnlessReplace) {
  TempDir dir;
  auto store = OpenDemoStore(dir.path());
  v1::RetargetClipRequest request = Request("demo_walk", "demo_character");
  v1::RetargetClipResponse response;
  ASSERT_TRUE(RetargetClip(*store, Limits{}, request, &response).ok());
  EXPECT_EQ(RetargetClip(*store, Limits{}, request, &response).code(), StatusCode::kAlreadyExists);
  request.set_replace(true);
  EXPECT_TRUE(RetargetClip(*store, Limits{}, request, &response).ok());
}

}  // namespace
}  // namespace armature::server
