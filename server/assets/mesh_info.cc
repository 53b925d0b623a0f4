// MeshInfo lives apart from proto_convert.cc because it is the one converter
// that needs the Mesh type.
#include "armature/engine/mesh/mesh.h"
#include "server/rpc/proto_convert.h"


namespace armature::server {

v1::MeshInfo MeshInfoOf(const StoredAsset& asset, const NamedMesh& m) {
  v1::MeshInfo info;
  info.set_name(m.name);
  info.set_asset(asset.record.name);
  info.set_skeleton(m.skeleton);
  if (m.mesh) {
    info.set_vertex_count(static_cast<int32_t>(m.mesh->vertex_count()));
    info.set_triangle_count(static_cast<int32_t>(m.mesh->triangle_count()));
    info.set_max_influences(static_cast<int32_t>(m.mesh->max_influences()));
    for (const auto& t : m.mesh->targets) info.add_target_names(t.name);
  }
  return info;
}

}  // namespace armature::server
