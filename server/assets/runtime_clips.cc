#include "server/assets/runtime_clips.h"

#include <spdlog/spdlog.h>

#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "armature/engine/anim/compression/compressed_clip.h"

namespace armature::server {

Status CompressClips(AssetContents& contents, const ClipPrecision& precision) {
  bool released = false;
  for (NamedClip& named : contents.clips) {
    if (!named.clip) continue;
    auto runtime = CompressClip(named.clip, precision);
    if (!runtime.ok()) return runtime.status().WithContext("clip '" + named.name + "': ");
    named.runtime = std::move(*runtime);
    // The file form leaves memory: an exact runtime form holds it as its keys; a lossy one replaces it
    // (export writes the runtime form's keys, ClipKeysOf).
    if (!named.runtime->exact()) {
      named.clip.reset();
      released = true;
    }
    if (!named.runtime->warning.empty()) {
      spdlog::warn("clip '{}': {}", named.name, named.runtime->warning);
      contents.warnings.push_back("clip '" + named.name + "': " + named.runtime->warning);
    }
  }
#ifdef __GLIBC__
  // The file form is ~25x the compressed one and freed here, but glibc keeps
  // freed pages in its per-thread arenas: a server that imported a library
  // held twice the RSS its assets count. Give them back.
  if (released) malloc_trim(0);
#endif
  return Status::Ok();
}

}  // namespace armature::server
