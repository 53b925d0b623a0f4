// Clips' runtime form in the server: compiled once when an asset is parsed
// (import, or load from the data dir) and kept beside the file form in
// NamedClip, which stays for export, motions and joint maps.
#pragma once

#include <span>

#include "armature/base/status.h"
#include "armature/engine/anim/clip.h"
#include "armature/engine/io/asset.h"
#include "armature/engine/math/transform.h"

namespace armature::server {

// Sets each clip's `compiled` (CompileClip). A clip that does not compile
// keeps none and is sampled from its file form (logged, never an error).
void CompileClips(AssetContents& contents);

// The runtime form to sample `clip` with: its `compiled` when that is of this
// very clip (a NamedClip copied and given another clip keeps the file form),
// else null.
const CompiledClip* RuntimeForm(const NamedClip& clip);

// SampleClip on a named clip: through its runtime form when it has one for
// this very clip (SampleCompiledClip), else the file form. Same checks and
// poses (float keys: within 1e-6, see compiled_clip.h). No allocation.
Status SampleNamedClip(const NamedClip& clip, double time, const SampleOptions& options, std::span<Trs> out);

// For benchmarks only (bench/evaluate_rpc_bench.cc): true makes
// SampleNamedClip use every clip's file form, as before the runtime form, so
// one run times both.
void SampleFileFormOnly(bool file_form);

}  // namespace armature::server
