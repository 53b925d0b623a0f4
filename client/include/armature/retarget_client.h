// AuthoringService.RetargetClip from C++, on a Client's channel, deadline and
// credentials (Client::Call). Failures throw armature::ClientError.
#pragma once

#include "armature/client.h"
#include "armature/v1/authoring.grpc.pb.h"

namespace armature {

// A clip moved onto another skeleton and stored as a new asset; the answer
// holds the new clip, its asset, the joint pairs used and the unmapped joints.
v1::RetargetClipResponse RetargetClip(const Client& client, const v1::RetargetClipRequest& request);

}  // namespace armature
