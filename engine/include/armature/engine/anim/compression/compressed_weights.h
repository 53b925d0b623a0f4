// A clip's morph weights in its compressed runtime form (issue 30): per
// mesh, each target's weight at the clip's compression frames, quantized in
// its own range with a bit rate and a sample stride chosen so that every
// frame's weight is within a stated weight bound (interpolated between the
// kept samples). The weight bound is the clip's bound over its shell
// distance (0.01 / 3 by default): a morph target that moves vertices by up to
// the shell distance then moves them by at most the bound, as the virtual
// points of a joint do. An exact clip keeps its weight keys as stored.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "armature/engine/anim/clip.h"
#include "armature/engine/anim/compression/error_bound.h"
#include "armature/engine/anim/compression/shell_error.h"

namespace armature {

struct CompressedWeights {
  // One target's samples: value = min + scale · q, q a `bits`-bit integer
  // (0 bits: constant min), at frames 0, stride, 2·stride, … and the last.
  struct Target {
    float min = 0, scale = 0;
    uint32_t bit_offset = 0;  // in `data`
    uint8_t bits = 0, stride_log = 0;
  };
  std::string mesh;  // the mesh asset's local name inside its file
  std::vector<Target> targets;
  std::vector<uint8_t> data;  // padded for 64-bit reads

  size_t ByteSize() const;
};

// The largest weight error `CompressWeights` allows under a clip bound.
double WeightBound(const ErrorBound& bound);

// `track` sampled at `frames` and quantized within `weight_bound`; nothing
// when 24 bits on every frame do not reach it. `worst` gets the largest
// weight error over the frames.
std::optional<CompressedWeights> CompressWeights(const WeightsTrack& track, const FrameGrid& frames,
                                                 double weight_bound, double& worst);

// The weights at clip time `time` (clamped; STEP holds the frame at or
// before it, else linear between frames) into `out` (size ≥ targets).
void SampleCompressedWeights(const CompressedWeights& weights, const FrameGrid& frames, double time,
                             const std::optional<Interpolation>& interpolation, std::span<double> out);

// The weights back as keys at the frames, for export.
WeightsTrack WeightsKeysOf(const CompressedWeights& weights, const FrameGrid& frames, double duration);

}  // namespace armature
