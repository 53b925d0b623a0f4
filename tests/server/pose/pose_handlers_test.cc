// The pose slice's handlers, called directly over an in-memory catalog.
#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"
#include "armature/engine/anim/clip.h"
#include "armature/engine/kinematics/fk.h"
#include "server/pose/pose_handlers.h"

namespace armature::server {
namespace {

using test_util::DemoCatalog;

TEST(PoseHandlers, EvaluateClipInWorldSpaceIsTheSampledPoseThroughFk) {
  auto catalog = DemoCatalog();
  v1::EvaluateClipRequest request;
  request.set_clip("demo_walk");
  request.add_times(0.4);
  request.set_space(v1::WORLD);
  v1::EvaluateClipResponse response;
  const Limits limits;
  const Status st = EvaluateClip(*catalog, limits, request, &response);
  ASSERT_TRUE(st.ok()) << st.message();
  ASSERT_EQ(response.poses_size(), 1);

  // The same pose from the engine directly.
  const auto clip_keys = test_util::StoredKeys(*catalog->FindClip("demo_walk")->part);
  const Clip& clip = *clip_keys;
  const Skeleton& skeleton = *clip.skeleton;
  std::vector<Trs> local(skeleton.size());
  ASSERT_TRUE(SampleClip(clip, 0.4, SampleOptions{}, local).ok());
  std::vector<Eigen::Affine3d> world(skeleton.size());
  std::vector<Eigen::Quaterniond> world_rotation(skeleton.size());
  ComputeWorld(skeleton, local, world, world_rotation);

  ASSERT_EQ(response.joints_size(), static_cast<int>(skeleton.size()));
  const auto& t = response.poses(0).translations();
  for (int i = 0; i < response.joints_size(); ++i) {
    const Eigen::Vector3d p = world[response.joints(i)].translation();
    for (int k = 0; k < 3; ++k) EXPECT_NEAR(t[3 * i + k], p[k], 1e-3) << skeleton.names[response.joints(i)];
  }
}

TEST(PoseHandlers, AnUnknownClipIsNotFoundNamingTheField) {
  auto catalog = DemoCatalog();
  v1::EvaluateClipRequest request;
  request.set_clip("demo_run");
  request.add_times(0);
  v1::EvaluateClipResponse response;
  const Status st = EvaluateClip(*catalog, Limits{}, request, &response);
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_NE(st.message().find("demo_run"), std::string::npos) << st.message();
}

}  // namespace
}  // namespace armature::server
