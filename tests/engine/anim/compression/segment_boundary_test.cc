// A compressed clip is continuous across its segments' boundaries: a segment
// ends on the next one's first sample, decoded as that segment decodes it.
// Sampled just before and just after every frame of CMU 01_01 (so every
// boundary, whatever the segments' length), the compressed clip moves no
// more than the clip as stored moves between the same two times (plus float
// rounding); each segment quantizing the shared frame in its own range left
// steps of up to 8.8e-5 rad.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "../../testing/shared_clips.h"

namespace armature {
namespace {

std::shared_ptr<const Clip> Cmu() { return test_util::SharedCmuClip(); }

// The largest change of any joint between two poses: rotation angles (rad)
// and translation distances (skeleton units), kept apart.
struct PoseChange {
  double angle = 0, distance = 0;
};

std::vector<PoseChange> Changes(const std::vector<Trs>& a, const std::vector<Trs>& b) {
  std::vector<PoseChange> out(a.size());
  for (size_t j = 0; j < a.size(); ++j) {
    out[j].angle = a[j].rotation.angularDistance(b[j].rotation);
    out[j].distance = (a[j].translation - b[j].translation).norm();
  }
  return out;
}

struct Sampler {
  const CompressedClip& clip;
  ClipSamplingContext context{clip};
  std::vector<Trs> pose = std::vector<Trs>(clip.skeleton->size());

  // Random access (no context) or sequential (the context, playing forward).
  const std::vector<Trs>& At(double t, bool sequential) {
    EXPECT_TRUE((ClipSamplingJob{&clip, t, WrapMode::kClamp, sequential ? &context : nullptr, pose, {}}.Run().ok()));
    return pose;
  }
};

TEST(SegmentBoundary, SamplingIsContinuousAtEveryFrame) {
  if (!Cmu()) GTEST_SKIP() << "../shared/data is absent";
  auto compressed = CompressClip(Cmu());
  ASSERT_TRUE(compressed.ok()) << compressed.status().message();
  const CompressedClip& z = **compressed;
  ASSERT_FALSE(z.exact()) << z.warning;
  ASSERT_EQ(z.frames.count, Cmu()->frame_count);  // 120 fps: its own frames
  const size_t n = z.skeleton->size();
  // ± a ten-thousandth of a frame: the clip as stored moves about 1e-5 rad at most.
  const double dt = z.frames.frame_time, delta = 1e-4 * dt;
  // Float rounding of the decoded samples and of the position in the segment.
  const double angle_rounding = 1e-6, distance_rounding = 1e-6;
  Sampler sampler{z}, whole_frames{z};
  std::vector<Trs> stored_before(n), stored_after(n);
  double worst_angle_excess = 0, worst_distance_excess = 0;
  size_t checked = 0;
  for (bool sequential : {false, true}) {
    for (size_t f = 1; f + 1 < z.frames.count; ++f, ++checked) {
      const double t = z.frames.Time(f);
      ASSERT_TRUE(SampleClip(*Cmu(), t - delta, {}, stored_before).ok());
      ASSERT_TRUE(SampleClip(*Cmu(), t + delta, {}, stored_after).ok());
      const std::vector<PoseChange> stored = Changes(stored_before, stored_after);
      // The compressed clip's own rate over the frames either side: it is
      // linear between samples, so it moves that rate × 2δ where continuous.
      const std::vector<Trs> previous = whole_frames.At(t - dt, false), at = whole_frames.At(t, false);
      const std::vector<PoseChange> left = Changes(previous, at), right = Changes(at, whole_frames.At(t + dt, false));
      const std::vector<Trs> before = sampler.At(t - delta, sequential);
      const std::vector<PoseChange> compressed_change = Changes(before, sampler.At(t + delta, sequential));
      for (size_t j = 0; j < n; ++j) {
        const double angle_excess =
            compressed_change[j].angle - 2 * stored[j].angle - (left[j].angle + right[j].angle) * delta / dt;
        const double distance_excess = compressed_change[j].distance - 2 * stored[j].distance -
                                       (left[j].distance + right[j].distance) * delta / dt -
                                       distance_rounding * before[j].translation.norm();
        worst_angle_excess = std::max(worst_angle_excess, angle_excess);
        worst_distance_excess = std::max(worst_distance_excess, distance_excess);
        EXPECT_LE(angle_excess, angle_rounding) << "frame " << f << " joint " << j << " sequential " << sequential;
        EXPECT_LE(distance_excess, distance_rounding)
            << "frame " << f << " joint " << j << " sequential " << sequential;
      }
    }
  }
  EXPECT_EQ(checked, 2 * (z.frames.count - 2));
  std::printf("frames checked: %zu; worst step over the stored motion: %.3g rad, %.3g units\n", checked,
              worst_angle_excess, worst_distance_excess);
}

// Sampling at a frame itself gives the pose its left side's interpolation
// tends to, up to float rounding of the interpolation weight.
TEST(SegmentBoundary, AFrameIsTheLimitFromTheLeft) {
  if (!Cmu()) GTEST_SKIP() << "../shared/data is absent";
  auto compressed = CompressClip(Cmu());
  ASSERT_TRUE(compressed.ok()) << compressed.status().message();
  const CompressedClip& z = **compressed;
  Sampler at_frame{z}, just_before{z};
  const double dt = z.frames.frame_time;
  double worst = 0;
  for (size_t f = 1; f + 1 < z.frames.count; ++f) {
    const std::vector<Trs> frame = at_frame.At(z.frames.Time(f), false);
    const std::vector<PoseChange> step = Changes(frame, just_before.At(z.frames.Time(f) - 1e-6 * dt, false));
    for (const PoseChange& c : step) worst = std::max(worst, c.angle);
  }
  EXPECT_LE(worst, 1e-5);  // about 1e-6 of a frame's motion, plus rounding
}

}  // namespace
}  // namespace armature
