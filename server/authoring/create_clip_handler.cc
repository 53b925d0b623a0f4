#include "server/authoring/create_clip_handler.h"

namespace armature::server {

// Placeholder until keyframe authoring lands (issue 14); answers, never crashes.
Status CreateClip(AssetStore&, const Limits&, const v1::CreateClipRequest&, v1::CreateClipResponse*) {
  return Status::FailedPrecondition("CreateClip is not available in this build");
}

}  // namespace armature::server
