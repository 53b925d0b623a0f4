#include "server/assets/compiled_clips.h"

#include <atomic>

#include <spdlog/spdlog.h>

#include "armature/engine/anim/compiled_clip.h"

namespace armature::server {
namespace {

std::atomic<bool> file_form_only{false};  // SampleFileFormOnly

}  // namespace

void CompileClips(AssetContents& contents) {
  for (NamedClip& named : contents.clips) {
    if (!named.clip) continue;
    auto compiled = CompileClip(named.clip);
    if (compiled.ok()) {
      named.compiled = std::move(*compiled);
    } else {
      spdlog::warn("clip '{}' has no runtime form (sampled from its file form): {}", named.name,
                   compiled.status().message());
    }
  }
}

const CompiledClip* RuntimeForm(const NamedClip& clip) {
  if (!clip.compiled || clip.compiled->source != clip.clip || file_form_only.load(std::memory_order_relaxed))
    return nullptr;
  return clip.compiled.get();
}

Status SampleNamedClip(const NamedClip& clip, double time, const SampleOptions& options, std::span<Trs> out) {
  const CompiledClip* compiled = RuntimeForm(clip);
  if (compiled == nullptr) return SampleClip(*clip.clip, time, options, out);
  ARMATURE_RETURN_IF_ERROR(SampleCompiledClip(*compiled, time, options, out));
  // Unit in double, as the file form's rotations are: float keys leave |q| - 1 near 1e-7, which
  // rotation matrices (ComputeWorld) and quaternion products (IK) would turn into different floats.
  // One Newton step toward 1/|q| (no sqrt, no division) takes it to about 1e-14.
  for (Trs& joint : out) joint.rotation.coeffs() *= 0.5 * (3.0 - joint.rotation.squaredNorm());
  return Status::Ok();
}

void SampleFileFormOnly(bool file_form) { file_form_only.store(file_form, std::memory_order_relaxed); }

}  // namespace armature::server
