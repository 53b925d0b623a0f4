// A crowd session's frames (CrowdService.CrowdSession) decoded to arrays: the
// decoder keeps each clip's CrowdLayout from the frame that brought it and
// turns a frame's encoded poses into local poses, as EvaluateClip's LOCAL
// space gives them. The encoding is described in crowd.proto (CrowdLayout).
#pragma once

#include <cstdint>
#include <map>
#include <vector>

#include "armature/v1/crowd.pb.h"

namespace armature::client {

// One frame's updated characters: per character `joints` transforms.
struct CrowdPoses {
  uint32_t joints = 0;  // the most joints of the characters' layouts (fewer: the rest padded with identity)
  std::vector<uint32_t> ids;
  std::vector<double> clip_times;
  std::vector<float> rotations;     // ids × joints × 4: w, x, y, z
  std::vector<float> translations;  // ids × joints × 3
  std::vector<float> scales;        // ids × joints × 3
};

class CrowdDecoder {
 public:
  // Decodes `frame` (reading its new layouts first). Throws ClientError
  // (INTERNAL) for poses that do not match their layouts.
  CrowdPoses Decode(const v1::CrowdFrame& frame);
  const v1::CrowdLayout* layout(uint32_t number) const;

 private:
  std::map<uint32_t, v1::CrowdLayout> layouts_;
};

}  // namespace armature::client
