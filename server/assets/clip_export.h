// ExportClip's work over a catalog snapshot, callable without gRPC.
#pragma once

#include "armature/base/status.h"
#include "armature/v1/assets.pb.h"
#include "server/assets/catalog.h"
#include "server/rpc/limits.h"
#include "server/rpc/reply_size.h"

namespace armature::server {

// The clip in the request's format (bvh, the default; glb; gltf). The answer's
// size is estimated first, in `encoding` (JSON carries the file as base64),
// and an answer over --max-message-mb is RESOURCE_EXHAUSTED before the work.
Status ExportClip(const Catalog& catalog, const Limits& limits, const v1::ExportClipRequest& request,
                  v1::ExportClipResponse* response, ReplyEncoding encoding = ReplyEncoding::kProtobuf);

}  // namespace armature::server
