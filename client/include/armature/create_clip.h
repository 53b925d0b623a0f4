// AuthoringService.CreateClip from C++: a clip from keys per joint, stored
// as a new asset on the server. Failures throw armature::ClientError.
#pragma once

#include "armature/client.h"
#include "armature/v1/authoring.grpc.pb.h"

namespace armature {

v1::CreateClipResponse CreateClip(const Client& client, const v1::CreateClipRequest& request);

}  // namespace armature
