// Caps on what one import may build. Importers check them (and what the
// input's bytes can actually hold) before allocating, so a small hostile file
// cannot make the engine reserve gigabytes. Going over a cap is
// RESOURCE_EXHAUSTED naming the cap's field, e.g. "... over the import limit
// max_clip_frames = 1000000"; the server sets them from its flags.
#pragma once

#include <cstdint>
#include <string>

#include "armature/base/status.h"

namespace armature {

struct ImportLimits {
  // Frames of one clip: BVH "Frames:", keys of one glTF sampler.
  uint64_t max_clip_frames = 1000000;
  // Keys summed over all tracks of one clip (≈ frames × animated joints).
  uint64_t max_clip_keys = uint64_t{1} << 25;
  // Vertices of one mesh.
  uint64_t max_mesh_vertices = 5000000;
  // Morph targets × vertices of one mesh.
  uint64_t max_morph_target_vertices = uint64_t{1} << 27;
  // Numbers decoded from all glTF accessors of one import (an accessor read
  // twice counts twice).
  uint64_t max_accessor_values = uint64_t{1} << 27;
  // count × element bytes of one glTF accessor without a bufferView (zeros
  // that no bytes of the file pay for).
  uint64_t max_unbacked_accessor_bytes = uint64_t{64} << 20;
  // Estimated bytes of what one import builds in memory (a mesh's vertices,
  // triangles, skin influences, morph deltas and skinning layout; a clip's
  // keys; the decoding's own copies), summed before each part is decoded. An
  // accessor used by several meshes or targets counts once per use.
  uint64_t max_decoded_bytes = uint64_t{1} << 30;
  // Bytes of one image as stored (encoded; images are never decoded).
  uint64_t max_image_bytes = uint64_t{32} << 20;
};

// "<what> <value> is over the import limit <field> = <limit>" as RESOURCE_EXHAUSTED text.
std::string OverImportLimit(const std::string& what, uint64_t value, const char* field, uint64_t limit);

// "<value> <unit> is over the import limit <field> = <limit>" (e.g. "160 vertices ...").
std::string OverImportLimitCount(uint64_t value, const std::string& unit, const char* field, uint64_t limit);

// Adds `bytes` to `*total` (saturating); RESOURCE_EXHAUSTED "<where>: the
// estimated memory of the parts decoded so far, ... max_decoded_bytes ..." once
// the sum passes limits.max_decoded_bytes.
Status ChargeDecodedBytes(uint64_t* total, uint64_t bytes, const ImportLimits& limits, const std::string& where);

}  // namespace armature
