// Motion messages → the engine's Motion: clips found in the catalog, each
// field carried over or defaulted, errors prefixed with the message's field.
#include "server/assets/motion_convert.h"

#include <gtest/gtest.h>

#include "../testing/demo_catalog.h"

namespace armature::server {
namespace {

TEST(MotionConvert, EveryFieldIsCarriedOverAndUnsetOnesDefault) {
  auto catalog = test_util::DemoCatalog();
  v1::Motion motion;
  motion.set_sync(v1::Motion::PHASE);
  motion.set_root_motion(v1::Motion::EXTRACT);
  motion.set_root_joint("Hips");
  v1::MotionLayer* base = motion.add_layers();
  base->set_clip("demo_walk");
  v1::MotionLayer* top = motion.add_layers();
  top->set_clip("demo_character.walk");
  top->set_weight(0.25);
  top->set_speed(2);
  top->set_time_offset(0.5);
  top->set_mode(v1::MotionLayer::ADDITIVE);
  top->set_reference_time(0.1);
  top->set_wrap(v1::CLAMP);
  top->add_mask("LeftShoulder");
  top->add_mask("RightShoulder");
  top->add_mask_weights(0.5);
  top->add_mask_weights(0.75);
  auto out = MotionFromProto(*catalog, motion, Limits{}, "motion");
  ASSERT_TRUE(out.ok()) << out.status().message();
  EXPECT_EQ(out->sync, TimeSync::kPhase);
  EXPECT_EQ(out->root_motion, RootMotion::kExtract);
  EXPECT_EQ(out->root_joint, "Hips");
  ASSERT_EQ(out->layers.size(), 2u);
  const MotionLayer& b = out->layers[0];
  EXPECT_EQ(b.clip, catalog->FindClip("demo_walk")->part->runtime);
  EXPECT_EQ(b.clip_name, "demo_walk");
  EXPECT_EQ(b.weight, 1.0);
  EXPECT_EQ(b.speed, 1.0);
  EXPECT_EQ(b.mode, LayerMode::kOverride);
  EXPECT_EQ(b.wrap, WrapMode::kLoop);  // layers loop unless told
  EXPECT_TRUE(b.mask.empty());
  const MotionLayer& t = out->layers[1];
  EXPECT_EQ(t.clip, catalog->FindClip("demo_character.walk")->part->runtime);
  EXPECT_EQ(t.weight, 0.25);
  EXPECT_EQ(t.speed, 2.0);
  EXPECT_EQ(t.time_offset, 0.5);
  EXPECT_EQ(t.mode, LayerMode::kAdditive);
  EXPECT_EQ(t.reference_time, 0.1);
  EXPECT_EQ(t.wrap, WrapMode::kClamp);
  ASSERT_EQ(t.mask.size(), 2u);
  EXPECT_EQ(t.mask[1].joint, "RightShoulder");
  EXPECT_EQ(t.mask[1].weight, 0.75);
}

TEST(MotionConvert, MaskJointsWithoutWeightsWeighOne) {
  auto catalog = test_util::DemoCatalog();
  v1::Motion motion;
  v1::MotionLayer* layer = motion.add_layers();
  layer->set_clip("demo_walk");
  layer->add_mask("Head");
  auto out = MotionFromProto(*catalog, motion, Limits{}, "m");
  ASSERT_TRUE(out.ok()) << out.status().message();
  ASSERT_EQ(out->layers[0].mask.size(), 1u);
  EXPECT_EQ(out->layers[0].mask[0].weight, 1.0);
}

TEST(MotionConvert, AnUnknownClipIsNotFoundNamingItsLayer) {
  auto catalog = test_util::DemoCatalog();
  v1::Motion motion;
  motion.add_layers()->set_clip("demo_walk");
  motion.add_layers()->set_clip("Wave");
  const Status st = MotionFromProto(*catalog, motion, Limits{}, "bake.motion").status();
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_TRUE(st.message().starts_with("bake.motion.layers[1]: ")) << st.message();
  EXPECT_NE(st.message().find("'Wave'"), std::string::npos) << st.message();
}

TEST(MotionConvert, TheMessageIsCheckedBeforeAnyLookup) {
  auto catalog = test_util::DemoCatalog();
  v1::Motion empty;
  const Status st = MotionFromProto(*catalog, empty, Limits{}, "motion").status();
  EXPECT_EQ(st.code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(st.message(), "motion.layers: the motion is empty (give at least one layer)");
  Limits one_layer;
  one_layer.max_motion_layers = 1;
  v1::Motion two;
  two.add_layers()->set_clip("Unknown");
  two.add_layers()->set_clip("Unknown");
  EXPECT_EQ(MotionFromProto(*catalog, two, one_layer, "motion").status().message(),
            "motion.layers: 2 layers, at most 1");
}

TEST(MotionConvert, BindingBindsOnTheFirstLayersSkeletonAndPrefixesItsErrors) {
  auto catalog = test_util::DemoCatalog();
  v1::Motion motion;
  motion.add_layers()->set_clip("demo_character.walk");
  motion.add_layers()->set_clip("demo_walk");
  auto plan = BindMotionProto(*catalog, motion, Limits{}, "motion");
  ASSERT_TRUE(plan.ok()) << plan.status().message();
  EXPECT_EQ(plan->skeleton, catalog->FindClip("demo_character.walk")->part->runtime->skeleton);
  ASSERT_EQ(plan->layers.size(), 2u);
  // The second layer's clip maps joint for joint by name onto the first's skeleton.
  const Skeleton& walk = *catalog->FindClip("demo_walk")->part->runtime->skeleton;
  for (size_t j = 0; j < plan->skeleton->size(); ++j)
    EXPECT_EQ(plan->layers[1].clip_joint[j], walk.Find(plan->skeleton->names[j]));

  motion.mutable_layers(1)->add_mask("Tail");
  const Status st = BindMotionProto(*catalog, motion, Limits{}, "motion").status();
  EXPECT_EQ(st.code(), StatusCode::kNotFound);
  EXPECT_EQ(st.message(), "motion.layers[1] (clip 'demo_walk'): mask joint 'Tail' is not in the skeleton");
}

}  // namespace
}  // namespace armature::server
