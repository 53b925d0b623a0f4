#include "server/authoring/retarget_handler.h"

namespace armature::server {

// Placeholder until the retargeting lands (issue 14); answers, never crashes.
Status RetargetClip(AssetStore&, const Limits&, const v1::RetargetClipRequest&, v1::RetargetClipResponse*) {
  return Status::FailedPrecondition("RetargetClip is not available in this build");
}

}  // namespace armature::server
