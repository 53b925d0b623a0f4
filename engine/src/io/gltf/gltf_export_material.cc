// glTF export of materials: PBR metallic-roughness factors, textures, their
// samplers and images (the stored bytes, in the buffer with their MIME type),
// each written once however many meshes share it.
#include <set>
#include <string>
#include <tuple>

#include "gltf_export.h"

namespace armature::gltf_export {

int MaterialWriter::Add(const Material& material) {
  if (auto it = materials_.find(&material); it != materials_.end()) return it->second;
  tinygltf::Material out;
  out.name = material.name;
  out.pbrMetallicRoughness.baseColorFactor.assign(material.base_color_factor.begin(), material.base_color_factor.end());
  out.pbrMetallicRoughness.metallicFactor = material.metallic_factor;
  out.pbrMetallicRoughness.roughnessFactor = material.roughness_factor;
  out.emissiveFactor.assign(material.emissive_factor.begin(), material.emissive_factor.end());
  out.alphaMode = material.alpha_mode;
  out.alphaCutoff = material.alpha_cutoff;
  out.doubleSided = material.double_sided;
  out.pbrMetallicRoughness.baseColorTexture.index = AddTexture(material.base_color_texture, material);
  out.pbrMetallicRoughness.metallicRoughnessTexture.index = AddTexture(material.metallic_roughness_texture, material);
  out.normalTexture.index = AddTexture(material.normal_texture, material);
  out.normalTexture.scale = material.normal_texture.scale;
  out.occlusionTexture.index = AddTexture(material.occlusion_texture, material);
  out.occlusionTexture.strength = material.occlusion_texture.scale;
  out.emissiveTexture.index = AddTexture(material.emissive_texture, material);
  tinygltf::Model& model = builder_.model();
  model.materials.push_back(std::move(out));
  const int index = static_cast<int>(model.materials.size()) - 1;
  materials_.emplace(&material, index);
  return index;
}

int MaterialWriter::AddTexture(const TextureRef& ref, const Material& material) {
  if (!ref.present() || static_cast<size_t>(ref.image) >= material.images.size() || !material.images[ref.image])
    return -1;
  const int image = AddImage(*material.images[static_cast<size_t>(ref.image)]);
  const int sampler = AddSampler(ref.sampler);
  tinygltf::Model& model = builder_.model();
  for (size_t t = 0; t < model.textures.size(); ++t)
    if (model.textures[t].source == image && model.textures[t].sampler == sampler) return static_cast<int>(t);
  tinygltf::Texture texture;
  texture.source = image;
  texture.sampler = sampler;
  model.textures.push_back(std::move(texture));
  return static_cast<int>(model.textures.size()) - 1;
}

int MaterialWriter::AddImage(const MaterialImage& image) {
  if (auto it = images_.find(&image); it != images_.end()) return it->second;
  tinygltf::Image out;
  out.name = image.name;
  out.mimeType = image.mime_type;
  out.bufferView = builder_.AddBytes(image.bytes);
  out.as_is = true;  // written as the bytes it holds, never re-encoded
  tinygltf::Model& model = builder_.model();
  model.images.push_back(std::move(out));
  const int index = static_cast<int>(model.images.size()) - 1;
  images_.emplace(&image, index);
  return index;
}

int MaterialWriter::AddSampler(const TextureSampler& s) {
  tinygltf::Model& model = builder_.model();
  for (size_t i = 0; i < model.samplers.size(); ++i) {
    const tinygltf::Sampler& m = model.samplers[i];
    if (std::tie(m.magFilter, m.minFilter, m.wrapS, m.wrapT) ==
        std::make_tuple(s.mag_filter ? s.mag_filter : -1, s.min_filter ? s.min_filter : -1, s.wrap_s, s.wrap_t))
      return static_cast<int>(i);
  }
  tinygltf::Sampler out;
  out.magFilter = s.mag_filter ? s.mag_filter : -1;
  out.minFilter = s.min_filter ? s.min_filter : -1;
  out.wrapS = s.wrap_s;
  out.wrapT = s.wrap_t;
  model.samplers.push_back(std::move(out));
  return static_cast<int>(model.samplers.size()) - 1;
}

uint64_t MaterialByteEstimate(std::span<const Mesh* const> meshes, uint64_t* json) {
  std::set<const Material*> materials;
  std::set<const MaterialImage*> images;
  uint64_t bin = 0;
  for (const Mesh* mesh : meshes) {
    bin = Add(bin, Mul(8, mesh->uvs.size()));
    // A primitive per group, each with its own indices view (4 bytes of alignment).
    *json = Add(*json, Mul(kJsonBytesPerObject * 3, mesh->material_groups.size()));
    bin = Add(bin, Mul(4, mesh->material_groups.size()));
    for (const auto& material : mesh->materials) {
      if (!material || !materials.insert(material.get()).second) continue;
      *json = Add(*json, Add(Mul(kJsonBytesPerObject, 4), Mul(6, material->name.size())));
      for (const auto& image : material->images)
        if (image && images.insert(image.get()).second) {
          bin = Add(bin, Add(image->bytes.size(), 4));
          *json = Add(*json, Add(Mul(kJsonBytesPerObject, 3), Mul(6, image->name.size() + image->mime_type.size())));
        }
    }
  }
  return bin;
}

}  // namespace armature::gltf_export
