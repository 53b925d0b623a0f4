// MeshInfo lives apart from proto_convert.cc because it is the one converter
// that needs the Mesh type.
#include "server/proto_convert.h"

namespace armature::server {

v1::MeshInfo MeshInfoOf(const StoredAsset& asset, const NamedMesh& m) {
  v1::MeshInfo info;
  info.set_name(m.name);
  info.set_asset(asset.record.name);
  info.set_skeleton(m.skeleton);
  return info;
}

}  // namespace armature::server
