// Compression and the sampling job on every clip of any file the importers
// accept (the input as engine_detect_fuzz's: "<format>/<filename>", a line
// break, the file), at the default bound, as the server compresses every
// import: the clip is
// compressed or refused with a status; a lossy runtime form samples finite
// poses through the job (in order, at random, without a context), and its
// error, measured here at every frame against the source, is within the
// bound it claims (a clip that cannot meet it must be stored exact).
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <optional>
#include <string_view>
#include <vector>

#include "armature/base/utf8.h"
#include "armature/engine/anim/compression/clip_sampling_job.h"
#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/io/asset.h"
#include "detect_input.h"
#include "fuzz_limits.h"

namespace {

using namespace armature;

// Grids past this many joint-samples compress within their stated bound
// (kMaxResampledJointSamples) but take seconds under the sanitizers, past
// libFuzzer's -timeout; the bug shapes are small clips. A grid over the cap
// itself (nullopt) is cheap and still compressed: it is stored exact.
constexpr double kMaxFuzzJointSamples = 20000;

[[noreturn]] void Fail(const char* what, double value = 0) {
  std::fprintf(stderr, "%s (%g)\n", what, value);
  std::abort();
}

bool Finite(const Trs& p) {
  return p.rotation.coeffs().allFinite() && p.translation.allFinite() && p.scale.allFinite();
}

// The job at `t` through `context` (or none), every transform finite and
// every rotation unit.
void SampleChecked(const CompressedClip& z, double t, ClipSamplingContext* context, std::vector<Trs>& pose) {
  if (!ClipSamplingJob{&z, t, WrapMode::kClamp, context, pose, {}}.Run().ok()) Fail("sampling refused a valid job");
  for (const Trs& p : pose) {
    if (!Finite(p)) Fail("a sampled transform is not finite", t);
    if (std::abs(p.rotation.squaredNorm() - 1) > 1e-6) Fail("a sampled rotation is not unit", t);
  }
}

// One imported clip through CompressClip and the job.
void CheckCompression(const std::shared_ptr<const Clip>& clip) {
  const std::optional<FrameGrid> grid = CompressionFrames(*clip);
  if (grid && static_cast<double>(grid->count * clip->skeleton->size()) > kMaxFuzzJointSamples) return;
  auto compressed = CompressClip(clip);
  if (!compressed.ok()) {
    if (!IsValidUtf8(compressed.status().message())) Fail("a refusal that is not UTF-8");
    return;
  }
  const CompressedClip& z = **compressed;
  if (z.exact()) return;  // the stored keys, sampled by SampleClip (its own tests)
  if (!(z.error.worst <= z.bound.precision)) Fail("stored lossy above its bound", z.error.worst);
  std::vector<Trs> pose(z.skeleton->size());
  ClipSamplingContext in_order(z), at_random(z);
  const size_t frames = z.frames.count;
  for (size_t f = 0; f < frames; ++f)
    SampleChecked(z, (static_cast<double>(f) + 0.5) * z.frames.frame_time, &in_order, pose);
  for (size_t k = 0; k < frames; ++k) {
    const double t = static_cast<double>((k * 7919) % frames) * z.frames.frame_time;
    SampleChecked(z, t, &at_random, pose);
    SampleChecked(z, t, nullptr, pose);
  }
  // The bound, measured again from outside: the job against SampleClip of
  // the source at every frame (the compressor measures the same way; a
  // relative 1e-9 allows for the order of its sums).
  auto measured = MeasureClipError(*clip, z.frames, z.bound.shell_distance, [&](double t, std::span<Trs> out) {
    return ClipSamplingJob{&z, t, WrapMode::kClamp, &in_order, out, {}}.Run();
  });
  if (!measured.ok()) Fail("the error could not be measured");
  if (!(measured->worst <= z.bound.precision * (1 + 1e-9))) Fail("sampled above the bound", measured->worst);
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const fuzz::DetectInput in = fuzz::SplitDetectInput(data, size);
  auto detected = DetectFormat(in.format, in.filename, in.bytes);
  if (!detected.ok()) return 0;
  auto contents = ParseAsset(*detected, in.bytes, "f", {}, fuzz::Limits());
  if (!contents.ok()) return 0;
  for (const NamedClip& c : contents->clips) CheckCompression(c.clip);
  return 0;
}
