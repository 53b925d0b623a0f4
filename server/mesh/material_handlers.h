// The mesh slice's material calls: one of a mesh's materials (factors,
// textures, images' types and sizes) and one image's stored bytes.
#pragma once

#include "armature/base/status.h"
#include "armature/v1/meshes.pb.h"
#include "server/assets/catalog.h"
#include "server/rpc/limits.h"

namespace armature::server {

// A material index out of range is INVALID_ARGUMENT naming it and the count.
Status GetMaterial(const Catalog& catalog, const v1::GetMaterialRequest& request, v1::Material* response);
// The image's bytes as stored; its index is checked against the material's
// images and its size against the reply limit (imports cap it, max_image_bytes).
Status GetMaterialImage(const Catalog& catalog, const v1::GetMaterialImageRequest& request, v1::MaterialImage* response,
                        const Limits& limits);

}  // namespace armature::server
