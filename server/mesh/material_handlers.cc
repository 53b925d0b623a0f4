#include "server/mesh/material_handlers.h"

#include "armature/engine/mesh/material.h"
#include "armature/engine/mesh/mesh.h"
#include "server/rpc/request_validation.h"

namespace armature::server {
namespace {

// Material `index` of mesh `name` (whose catalog name goes to `found_name`).
StatusOr<const Material*> MaterialOfMesh(const Catalog& catalog, const std::string& name, int index,
                                         std::string* found_name) {
  auto ref = catalog.FindMesh(name);
  if (!ref.ok()) return ref.status().WithContext("mesh: ");
  *found_name = ref->part->name;
  const auto& materials = ref->part->mesh->materials;
  if (index < 0 || static_cast<size_t>(index) >= materials.size())
    return Status::InvalidArgument("material: " + std::to_string(index) + " is out of range (mesh '" + ref->part->name +
                                   "' has " + std::to_string(materials.size()) + " materials)");
  return materials[static_cast<size_t>(index)].get();
}

void TextureOf(const TextureRef& ref, v1::TextureRef* out) {
  out->set_image(ref.image);
  out->set_texcoord(ref.texcoord);
  out->set_scale(ref.scale);
  v1::TextureSampler* s = out->mutable_sampler();
  s->set_mag_filter(ref.sampler.mag_filter);
  s->set_min_filter(ref.sampler.min_filter);
  s->set_wrap_s(ref.sampler.wrap_s);
  s->set_wrap_t(ref.sampler.wrap_t);
}

}  // namespace

Status GetMaterial(const Catalog& catalog, const v1::GetMaterialRequest& request, v1::Material* response) {
  std::string mesh;
  ARMATURE_ASSIGN_OR_RETURN(auto found, MaterialOfMesh(catalog, request.mesh(), request.material(), &mesh));
  const Material& m = *found;
  response->set_mesh(mesh);
  response->set_index(request.material());
  response->set_name(m.name);
  response->mutable_base_color_factor()->Add(m.base_color_factor.begin(), m.base_color_factor.end());
  response->set_metallic_factor(m.metallic_factor);
  response->set_roughness_factor(m.roughness_factor);
  response->mutable_emissive_factor()->Add(m.emissive_factor.begin(), m.emissive_factor.end());
  response->set_alpha_mode(m.alpha_mode);
  response->set_alpha_cutoff(m.alpha_cutoff);
  response->set_double_sided(m.double_sided);
  const std::pair<const TextureRef*, v1::TextureRef* (v1::Material::*)()> slots[] = {
      {&m.base_color_texture, &v1::Material::mutable_base_color_texture},
      {&m.metallic_roughness_texture, &v1::Material::mutable_metallic_roughness_texture},
      {&m.normal_texture, &v1::Material::mutable_normal_texture},
      {&m.occlusion_texture, &v1::Material::mutable_occlusion_texture},
      {&m.emissive_texture, &v1::Material::mutable_emissive_texture},
  };
  for (const auto& [ref, field] : slots)
    if (ref->present()) TextureOf(*ref, (response->*field)());
  for (size_t i = 0; i < m.images.size(); ++i) {
    v1::MaterialImageInfo* info = response->add_images();
    info->set_index(static_cast<int>(i));
    info->set_name(m.images[i]->name);
    info->set_mime_type(m.images[i]->mime_type);
    info->set_byte_size(static_cast<int64_t>(m.images[i]->bytes.size()));
  }
  return Status::Ok();
}

Status GetMaterialImage(const Catalog& catalog, const v1::GetMaterialImageRequest& request, v1::MaterialImage* response,
                        const Limits& limits) {
  std::string mesh;
  ARMATURE_ASSIGN_OR_RETURN(auto found, MaterialOfMesh(catalog, request.mesh(), request.material(), &mesh));
  const Material& m = *found;
  const int index = request.image();
  if (index < 0 || static_cast<size_t>(index) >= m.images.size())
    return Status::InvalidArgument("image: " + std::to_string(index) + " is out of range (material " +
                                   std::to_string(request.material()) + " of mesh '" + mesh + "' has " +
                                   std::to_string(m.images.size()) + " images)");
  const MaterialImage& image = *m.images[static_cast<size_t>(index)];
  ARMATURE_RETURN_IF_ERROR(ValidateReplySize(static_cast<double>(image.bytes.size()), limits, "GetMaterialImage",
                                             "an image of " + std::to_string(image.bytes.size()) + " bytes"));
  response->set_mesh(mesh);
  response->set_material(request.material());
  response->set_image(index);
  response->set_name(image.name);
  response->set_mime_type(image.mime_type);
  response->set_data(image.bytes);
  return Status::Ok();
}

}  // namespace armature::server
