// The BVH texts the parse benchmarks share (bvh_bench.cc, bvh_assimp_bench.cc):
// the CMU capture from shared data, and a large file generated from the demo
// walk so that a run without shared data still measures something.
#pragma once

#include <algorithm>
#include <fstream>
#include <optional>
#include <sstream>
#include <string>

#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/demo_walk.h"

namespace armature_bench {

inline const std::optional<std::string>& CmuBvhText() {
  static const std::optional<std::string> text = []() -> std::optional<std::string> {
    std::ifstream in(std::string(ARMATURE_SHARED_DATA) + "/bvh/cmu_01_01.bvh", std::ios::binary);
    if (!in) return std::nullopt;
    std::stringstream ss;
    ss << in.rdbuf();
    return ss.str();
  }();
  return text;
}

// The demo walk written as BVH, its frame lines repeated until the text
// holds at least `min_bytes`, with Frames: saying how many there are.
inline std::string RepeatedWalkBvh(size_t min_bytes) {
  const std::string walk = armature::WriteBvh(*armature::MakeDemoWalk().clip);
  const size_t motion = walk.find("MOTION");
  const size_t frames_start = walk.find('\n', walk.find("Frame Time:")) + 1;
  const std::string frame_lines = walk.substr(frames_start);
  const size_t lines_per_copy = static_cast<size_t>(std::count(frame_lines.begin(), frame_lines.end(), '\n'));
  std::string body;
  body.reserve(min_bytes + frame_lines.size());
  size_t frames = 0;
  while (body.size() < min_bytes) {
    body += frame_lines;
    frames += lines_per_copy;
  }
  return walk.substr(0, motion) + "MOTION\nFrames: " + std::to_string(frames) + "\nFrame Time: 0.0333333\n" + body;
}

// ~16 MB: well beyond the caches, as a long capture session is.
inline const std::string& LargeWalkBvhText() {
  static const std::string text = RepeatedWalkBvh(16'000'000);
  return text;
}

}  // namespace armature_bench
