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
  if (const CompiledClip* compiled = RuntimeForm(clip)) return SampleCompiledClip(*compiled, time, options, out);
  return SampleClip(*clip.clip, time, options, out);
}

void SampleFileFormOnly(bool file_form) { file_form_only.store(file_form, std::memory_order_relaxed); }

}  // namespace armature::server
