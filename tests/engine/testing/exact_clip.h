// Tests: a clip's runtime form kept exact (the stored keys bit for bit), so a
// test comparing with a reference keeps its tolerance, and skinning by it.
#pragma once

#include <memory>
#include <span>

#include <gtest/gtest.h>

#include "armature/engine/anim/compression/compressed_clip.h"
#include "armature/engine/mesh/skinning.h"

namespace armature::test_util {

inline std::shared_ptr<const CompressedClip> ExactClip(std::shared_ptr<const Clip> clip) {
  auto compressed = CompressClip(std::move(clip), ClipPrecision{.exact = true});
  EXPECT_TRUE(compressed.ok()) << compressed.status().message();
  return compressed.ok() ? *compressed : nullptr;
}

inline std::shared_ptr<const CompressedClip> ExactClip(const Clip& clip) {
  return ExactClip(std::make_shared<const Clip>(clip));
}

// SkinClip on the exact form of `clip` (as the engine skinned a Clip before issue 30).
inline Status SkinExactClip(const Mesh& mesh, const Clip& clip, double time, const SampleOptions& sample,
                            const SkinningOptions& options, std::span<float> positions, std::span<float> normals,
                            SkinningWorkspace& workspace) {
  const auto exact = ExactClip(clip);
  if (!exact) return Status::InvalidArgument("clip does not compress");
  return SkinClip(mesh, *exact, {time, sample.wrap, sample.interpolation}, options, positions, normals, workspace);
}

}  // namespace armature::test_util
