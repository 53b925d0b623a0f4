// A mesh's material as glTF 2.0 describes it (PBR metallic-roughness: factors
// and textures) and the images its textures sample. Images keep the bytes the
// file stored (PNG, JPEG, ...): the engine never decodes them, a client does.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace armature {

struct MaterialImage {
  std::string name;       // the glTF image's name, or its index
  std::string mime_type;  // "image/png", "image/jpeg", ...
  std::string bytes;      // encoded, exactly as stored in the file
};

// GL enums as glTF stores them; 0: not set (a client picks, as glTF says).
struct TextureSampler {
  int mag_filter = 0;
  int min_filter = 0;
  int wrap_s = 10497;  // REPEAT
  int wrap_t = 10497;
};

struct TextureRef {
  int image = -1;    // index into Material::images; -1: no texture
  int texcoord = 0;  // the TEXCOORD_n set it samples (only TEXCOORD_0 is kept)
  double scale = 1;  // normalTexture.scale, occlusionTexture.strength; 1 otherwise
  TextureSampler sampler;
  bool present() const { return image >= 0; }
};

struct Material {
  std::string name;                                     // the glTF material's name, or its index
  std::array<double, 4> base_color_factor{1, 1, 1, 1};  // linear RGBA
  double metallic_factor = 1;
  double roughness_factor = 1;
  std::array<double, 3> emissive_factor{0, 0, 0};
  std::string alpha_mode = "OPAQUE";  // OPAQUE, MASK or BLEND
  double alpha_cutoff = 0.5;
  bool double_sided = false;
  TextureRef base_color_texture, metallic_roughness_texture, normal_texture, occlusion_texture, emissive_texture;
  // The images its textures use; shared with the other materials of the file.
  std::vector<std::shared_ptr<const MaterialImage>> images;
};

// A run of a mesh's triangles drawn with one material (a glTF primitive).
struct MaterialGroup {
  uint32_t first_triangle = 0;
  uint32_t triangle_count = 0;
  int material = -1;  // index into Mesh::materials; -1: none
};

}  // namespace armature
