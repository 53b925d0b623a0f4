// glTF materials → Material: PBR metallic-roughness factors, textures with
// their samplers, and the images as stored (bytes and MIME type, undecoded).
#include <algorithm>
#include <cmath>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "armature/base/utf8.h"
#include "gltf_importer.h"

namespace armature::gltf_internal {
namespace {

// The image's type from its first bytes; empty when none of these.
std::string SniffImageType(std::string_view b) {
  if (b.substr(0, 8) == std::string_view("\x89PNG\r\n\x1a\n", 8)) return "image/png";
  if (b.substr(0, 3) == "\xFF\xD8\xFF") return "image/jpeg";
  if (b.size() >= 12 && b.substr(0, 4) == "RIFF" && b.substr(8, 4) == "WEBP") return "image/webp";
  if (b.substr(0, 12) == "\xABKTX 20\xBB\r\n\x1A\n") return "image/ktx2";
  return "";
}

}  // namespace

StatusOr<std::shared_ptr<const MaterialImage>> Importer::ImageOf(int index) {
  const std::string where = "images[" + std::to_string(index) + "]";
  if (index < 0 || static_cast<size_t>(index) >= model_.images.size())
    return Status::InvalidArgument(where + " does not exist (file has " + std::to_string(model_.images.size()) + ")");
  if (images_.empty()) images_.resize(model_.images.size());
  auto& cached = images_[static_cast<size_t>(index)];
  if (cached) return cached;
  const tinygltf::Image& gi = model_.images[static_cast<size_t>(index)];
  ARMATURE_RETURN_IF_ERROR(CheckName(gi.name, where + ".name"));
  auto image = std::make_shared<MaterialImage>();
  image->name = gi.name.empty() ? std::to_string(index) : gi.name;
  uint64_t size = gi.image.size();
  const tinygltf::Buffer* buffer = nullptr;
  const tinygltf::BufferView* view = nullptr;
  if (gi.bufferView >= 0) {
    if (static_cast<size_t>(gi.bufferView) >= model_.bufferViews.size())
      return Status::InvalidArgument(where + ".bufferView " + std::to_string(gi.bufferView) + " does not exist");
    view = &model_.bufferViews[static_cast<size_t>(gi.bufferView)];
    if (view->buffer < 0 || static_cast<size_t>(view->buffer) >= model_.buffers.size())
      return Status::InvalidArgument(where + ": bufferView " + std::to_string(gi.bufferView) + " has no buffer");
    buffer = &model_.buffers[static_cast<size_t>(view->buffer)];
    if (view->byteOffset > buffer->data.size() || view->byteLength > buffer->data.size() - view->byteOffset)
      return Status::InvalidArgument(where + ": bufferView " + std::to_string(gi.bufferView) + " (bytes " +
                                     std::to_string(view->byteOffset) + " + " + std::to_string(view->byteLength) +
                                     ") runs past its buffer of " + std::to_string(buffer->data.size()) + " bytes");
    size = view->byteLength;
  }
  if (size > limits_.max_image_bytes)
    return Status::ResourceExhausted(where + ": " +
                                     OverImportLimitCount(size, "bytes", "max_image_bytes", limits_.max_image_bytes));
  if (size == 0) {
    warnings_.push_back(
        where + (gi.uri.empty() ? " has no bytes" : " uri '" + EscapeForMessage(gi.uri, 200) + "' was not provided") +
        "; the textures using it are dropped");
    return std::shared_ptr<const MaterialImage>();
  }
  if (view)
    image->bytes.assign(reinterpret_cast<const char*>(buffer->data.data()) + view->byteOffset, size);
  else
    image->bytes.assign(gi.image.begin(), gi.image.end());
  image->mime_type = SniffImageType(image->bytes);
  if (image->mime_type.empty()) {
    warnings_.push_back(where + " is not PNG, JPEG, WebP or KTX2; the textures using it are dropped");
    return std::shared_ptr<const MaterialImage>();
  }
  cached = std::move(image);
  return cached;
}

StatusOr<TextureRef> Importer::ReadTexture(int texture, int texcoord, double scale, const std::string& where,
                                           std::vector<std::shared_ptr<const MaterialImage>>& images) {
  TextureRef ref;
  if (texture < 0) return ref;
  if (static_cast<size_t>(texture) >= model_.textures.size())
    return Status::InvalidArgument(where + ".index: texture " + std::to_string(texture) + " does not exist (file has " +
                                   std::to_string(model_.textures.size()) + ")");
  if (!std::isfinite(scale)) return Status::InvalidArgument(where + ": scale is not finite");
  const tinygltf::Texture& gt = model_.textures[static_cast<size_t>(texture)];
  if (texcoord != 0 || gt.source < 0) {
    warnings_.push_back(where +
                        (texcoord != 0 ? " samples TEXCOORD_" + std::to_string(texcoord) + "; only TEXCOORD_0 is kept"
                                       : ": texture " + std::to_string(texture) + " has no source image") +
                        "; dropped");
    return ref;
  }
  auto image = ImageOf(gt.source);
  if (!image.ok()) return image.status().WithContext("textures[" + std::to_string(texture) + "].source: ");
  if (!*image) return ref;
  if (gt.sampler >= 0) {
    if (static_cast<size_t>(gt.sampler) >= model_.samplers.size())
      return Status::InvalidArgument("textures[" + std::to_string(texture) + "].sampler " + std::to_string(gt.sampler) +
                                     " does not exist");
    const tinygltf::Sampler& s = model_.samplers[static_cast<size_t>(gt.sampler)];
    ref.sampler = {std::max(s.magFilter, 0), std::max(s.minFilter, 0), s.wrapS, s.wrapT};
  }
  ref.scale = scale;
  ref.image = -1;
  for (size_t i = 0; i < images.size(); ++i)
    if (images[i] == *image) ref.image = static_cast<int>(i);
  if (ref.image < 0) {
    images.push_back(*image);
    ref.image = static_cast<int>(images.size()) - 1;
  }
  return ref;
}

StatusOr<std::shared_ptr<const Material>> Importer::MaterialOf(int index) {
  const std::string where = "materials[" + std::to_string(index) + "]";
  if (index < 0) return std::shared_ptr<const Material>();
  if (static_cast<size_t>(index) >= model_.materials.size())
    return Status::InvalidArgument(where + " does not exist (file has " + std::to_string(model_.materials.size()) +
                                   ")");
  if (materials_.empty()) materials_.resize(model_.materials.size());
  auto& cached = materials_[static_cast<size_t>(index)];
  if (cached) return cached;
  const tinygltf::Material& gm = model_.materials[static_cast<size_t>(index)];
  const tinygltf::PbrMetallicRoughness& pbr = gm.pbrMetallicRoughness;
  ARMATURE_RETURN_IF_ERROR(CheckName(gm.name, where + ".name"));
  ARMATURE_RETURN_IF_ERROR(CheckNumbers(pbr.baseColorFactor, {4}, where + ".pbrMetallicRoughness.baseColorFactor"));
  ARMATURE_RETURN_IF_ERROR(CheckNumbers(gm.emissiveFactor, {0, 3}, where + ".emissiveFactor"));
  ARMATURE_RETURN_IF_ERROR(CheckNumbers({pbr.metallicFactor, pbr.roughnessFactor, gm.alphaCutoff}, {3},
                                        where + " metallicFactor, roughnessFactor, alphaCutoff"));
  if (gm.alphaMode != "OPAQUE" && gm.alphaMode != "MASK" && gm.alphaMode != "BLEND")
    return Status::InvalidArgument(where + ".alphaMode '" + EscapeForMessage(gm.alphaMode, 40) +
                                   "' is not OPAQUE, MASK or BLEND");
  auto material = std::make_shared<Material>();
  material->name = gm.name.empty() ? std::to_string(index) : gm.name;
  for (size_t c = 0; c < 4; ++c) material->base_color_factor[c] = pbr.baseColorFactor[c];
  for (size_t c = 0; c < gm.emissiveFactor.size(); ++c) material->emissive_factor[c] = gm.emissiveFactor[c];
  material->metallic_factor = pbr.metallicFactor;
  material->roughness_factor = pbr.roughnessFactor;
  material->alpha_mode = gm.alphaMode;
  material->alpha_cutoff = gm.alphaCutoff;
  material->double_sided = gm.doubleSided;
  struct Slot {
    TextureRef* out;
    int index, texcoord;
    double scale;
    const char* field;
  };
  const Slot slots[] = {
      {&material->base_color_texture, pbr.baseColorTexture.index, pbr.baseColorTexture.texCoord, 1,
       ".pbrMetallicRoughness.baseColorTexture"},
      {&material->metallic_roughness_texture, pbr.metallicRoughnessTexture.index, pbr.metallicRoughnessTexture.texCoord,
       1, ".pbrMetallicRoughness.metallicRoughnessTexture"},
      {&material->normal_texture, gm.normalTexture.index, gm.normalTexture.texCoord, gm.normalTexture.scale,
       ".normalTexture"},
      {&material->occlusion_texture, gm.occlusionTexture.index, gm.occlusionTexture.texCoord,
       gm.occlusionTexture.strength, ".occlusionTexture"},
      {&material->emissive_texture, gm.emissiveTexture.index, gm.emissiveTexture.texCoord, 1, ".emissiveTexture"},
  };
  for (const Slot& slot : slots) {
    ARMATURE_ASSIGN_OR_RETURN(auto ref,
                              ReadTexture(slot.index, slot.texcoord, slot.scale, where + slot.field, material->images));
    *slot.out = ref;
  }
  cached = std::move(material);
  return cached;
}

}  // namespace armature::gltf_internal
