// CreateClip's keys: each check names the entry, the joint, the key and the
// problem; what passes becomes the engine's tracks, times as 32-bit floats.
#include "server/authoring/create_clip_validation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "armature/engine/io/demo_walk.h"

namespace armature::server {
namespace {

const Skeleton& Walk() {
  static const BvhData walk = MakeDemoWalk();
  return *walk.clip->skeleton;
}

// A request with one entry for `joint`, to be filled by the test.
v1::CreateClipRequest OneEntry(const std::string& joint, v1::JointKeys** entry) {
  v1::CreateClipRequest request;
  *entry = request.add_tracks();
  (*entry)->set_joint(joint);
  return request;
}

Status ErrorOf(const v1::CreateClipRequest& request, const Limits& limits = {}) {
  return KeyedJointsFromRequest(request, Walk(), "walk", limits).status();
}

TEST(CreateClipValidation, StoredKeyTimesAreTheFloatAtOrBelow) {
  for (double t : {0.1, 1.0 / 3, 2.7, 1e-3, 12345.678}) {
    const double stored = StoredKeyTime(t);
    EXPECT_LE(stored, t);
    EXPECT_EQ(static_cast<double>(static_cast<float>(stored)), stored);  // a float
    EXPECT_GT(std::nextafter(static_cast<float>(stored), INFINITY), t);  // the greatest such float
  }
  EXPECT_EQ(StoredKeyTime(0.5), 0.5);  // exact floats stay
}

TEST(CreateClipValidation, KeysBecomeTracksOnTheNamedJoint) {
  v1::JointKeys* e;
  auto request = OneEntry("Head", &e);
  for (double t : {0.0, 0.1, 0.5}) e->add_times(t);
  const double s = std::sqrt(0.5);
  for (double v : {1.0, 0.0, 0.0, 0.0, s, s, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0}) e->add_rotations(v);
  for (int k = 0; k < 9; ++k) e->add_translations(k);
  e->set_interpolation(v1::STEP);
  auto keyed = KeyedJointsFromRequest(request, Walk(), "walk", Limits{});
  ASSERT_TRUE(keyed.ok()) << keyed.status().message();
  ASSERT_EQ(keyed->size(), 1u);
  const KeyedJoint& k = (*keyed)[0];
  EXPECT_EQ(k.joint, Walk().Find("Head"));
  EXPECT_FALSE(k.remove);
  EXPECT_EQ(k.track.rotation.times, (std::vector<double>{0.0, StoredKeyTime(0.1), 0.5}));
  EXPECT_EQ(k.track.rotation.interpolation, Interpolation::kStep);
  // w, x, y, z in the request: the second key is 90° about X.
  EXPECT_NEAR(k.track.rotation.values[1].w(), s, 1e-12);
  EXPECT_NEAR(k.track.rotation.values[1].x(), s, 1e-12);
  EXPECT_NEAR(k.track.rotation.values[2].y(), 1, 1e-12);
  EXPECT_EQ(k.track.translation.values[2], Eigen::Vector3d(6, 7, 8));
  EXPECT_TRUE(k.track.scale.empty());
}

TEST(CreateClipValidation, EulerDegreesComposeInTheirOrder) {
  v1::JointKeys* e;
  auto request = OneEntry("Chest", &e);
  e->add_times(0);
  for (double deg : {30.0, 40.0, 50.0}) e->add_euler(deg);
  e->set_euler_order("ZXY");
  auto keyed = KeyedJointsFromRequest(request, Walk(), "walk", Limits{});
  ASSERT_TRUE(keyed.ok()) << keyed.status().message();
  const double r = M_PI / 180;
  const Eigen::Quaterniond expected = Eigen::AngleAxisd(30 * r, Eigen::Vector3d::UnitZ()) *
                                      Eigen::AngleAxisd(40 * r, Eigen::Vector3d::UnitX()) *
                                      Eigen::AngleAxisd(50 * r, Eigen::Vector3d::UnitY());
  EXPECT_NEAR(std::abs((*keyed)[0].track.rotation.values[0].dot(expected)), 1.0, 1e-12);
}

TEST(CreateClipValidation, AnUnknownJointIsNamedWithTheClosestOne) {
  v1::JointKeys* e;
  auto request = OneEntry("Haed", &e);
  e->add_times(0);
  const Status st = ErrorOf(request);
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_TRUE(st.message().starts_with("tracks[0] (joint 'Haed'): joint 'Haed' is not on skeleton 'walk'"))
      << st.message();
  EXPECT_NE(st.message().find("'Head'"), std::string::npos) << st.message();
}

TEST(CreateClipValidation, TimesMustIncreaseAlsoAsFloats) {
  const auto with_times = [](std::vector<double> times) {
    v1::JointKeys* e;
    auto request = OneEntry("Head", &e);
    for (double t : times) {
      e->add_times(t);
      for (double v : {1.0, 0.0, 0.0}) e->add_translations(v);
    }
    return ErrorOf(request).message();
  };
  EXPECT_EQ(with_times({0, 0.5, 0.4}),
            "tracks[0] (joint 'Head'): key 2: time 0.4 does not increase (key 1 is at 0.5); times must be sorted");
  EXPECT_EQ(with_times({0, 0.5, 0.5}), "tracks[0] (joint 'Head'): key 2: time 0.5 repeats key 1");
  EXPECT_EQ(with_times({-1}), "tracks[0] (joint 'Head'): key 0: time -1 is negative");
  EXPECT_EQ(with_times({0, NAN}), "tracks[0] (joint 'Head'): key 1: time is not finite");
  EXPECT_EQ(with_times({1, 1 + 3e-8}),
            "tracks[0] (joint 'Head'): key 1: time 1.00000003 equals key 0's 1 as a 32-bit float (glTF stores times "
            "as floats)");
}

TEST(CreateClipValidation, ValuesAreCountedPerKeyAndRotationsAreUnit) {
  v1::JointKeys* e;
  auto request = OneEntry("Head", &e);
  e->add_times(0);
  e->add_times(1);
  for (double v : {1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0}) e->add_rotations(v);
  EXPECT_EQ(ErrorOf(request).message(),
            "tracks[0] (joint 'Head'): rotations: 7 values for 2 keys; expected 4 per key (w, x, y, z), 8");
  e->add_rotations(0.1);  // second key's norm: sqrt(1.01)
  EXPECT_EQ(ErrorOf(request).message(),
            "tracks[0] (joint 'Head'): key 1: rotation is not a unit quaternion (norm 1.00498756, tolerance 1e-3)");
  e->set_rotations(7, 0.0);
  e->set_rotations(4, 1.0005);  // within the tolerance: normalized
  auto keyed = KeyedJointsFromRequest(request, Walk(), "walk", Limits{});
  ASSERT_TRUE(keyed.ok()) << keyed.status().message();
  EXPECT_DOUBLE_EQ((*keyed)[0].track.rotation.values[1].norm(), 1.0);
  e->add_translations(1e39);
  e->add_translations(0);
  e->add_translations(0);
  e->add_translations(0);
  e->add_translations(0);
  e->add_translations(0);
  EXPECT_EQ(ErrorOf(request).message(),
            "tracks[0] (joint 'Head'): key 0: translations value 1e+39 is beyond a 32-bit float");
}

TEST(CreateClipValidation, TangentsAreForCubicTracksOnly) {
  v1::JointKeys* e;
  auto request = OneEntry("Head", &e);
  e->add_times(0);
  for (double v : {0.0, 1.0, 2.0}) e->add_translations(v);
  for (double v : {0.0, 0.0, 0.0}) e->mutable_translation_tangents()->add_in_tangents(v);
  for (double v : {0.0, 0.0, 0.0}) e->mutable_translation_tangents()->add_out_tangents(v);
  EXPECT_EQ(ErrorOf(request).message(),
            "tracks[0] (joint 'Head'): translation_tangents: tangents are only for CUBIC tracks");
  e->set_interpolation(v1::CUBIC);
  auto keyed = KeyedJointsFromRequest(request, Walk(), "walk", Limits{});
  ASSERT_TRUE(keyed.ok()) << keyed.status().message();
  EXPECT_EQ((*keyed)[0].track.translation.in_tangents.size(), 1u);
  e->mutable_translation_tangents()->add_out_tangents(0);
  EXPECT_EQ(ErrorOf(request).message(),
            "tracks[0] (joint 'Head'): translation_tangents.outTangents: 4 values for 1 keys; expected 3 per key (x, "
            "y, z), 3");
  e->clear_translation_tangents();
  for (double v : {0.0, 0.0, 0.0}) e->mutable_scale_tangents()->add_in_tangents(v);
  EXPECT_EQ(ErrorOf(request).message(),
            "tracks[0] (joint 'Head'): scale_tangents: tangents for a channel without values");
}

TEST(CreateClipValidation, EntriesWithoutTimesDeleteOnlyWithMergeOrBake) {
  v1::JointKeys* e;
  auto request = OneEntry("Head", &e);
  EXPECT_EQ(ErrorOf(request).message(),
            "tracks[0] (joint 'Head'): no times: an entry without times deletes a stored or baked track, with merge "
            "or bake only");
  request.set_merge(true);
  auto keyed = KeyedJointsFromRequest(request, Walk(), "walk", Limits{});
  ASSERT_TRUE(keyed.ok()) << keyed.status().message();
  EXPECT_TRUE((*keyed)[0].remove);
  e->add_translations(1);
  EXPECT_EQ(ErrorOf(request).message(), "tracks[0] (joint 'Head'): values without times (give one time per key)");
}

TEST(CreateClipValidation, EachJointOnceAndNoMoreKeysThanMaxClipFrames) {
  v1::JointKeys* e;
  auto request = OneEntry("Head", &e);
  for (int k = 0; k < 3; ++k) {
    e->add_times(k);
    for (double v : {0.0, 0.0, 0.0}) e->add_translations(v);
  }
  *request.add_tracks() = *e;
  EXPECT_EQ(ErrorOf(request).message(),
            "tracks[1] (joint 'Head'): a second entry for this joint (give each joint once)");
  request.mutable_tracks()->RemoveLast();
  Limits two;
  two.max_clip_frames = 2;
  const Status st = ErrorOf(request, two);
  EXPECT_EQ(st.code(), StatusCode::kResourceExhausted);
  EXPECT_EQ(st.message(), "tracks[0] (joint 'Head'): 3 keys, over the limit of 2 keys per track (--max-clip-frames)");
}

}  // namespace
}  // namespace armature::server
