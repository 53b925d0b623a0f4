// The glTF writer's shared pieces: the model under construction with its one
// buffer (gltf_writer.cc, also used by demo_character.cc), the animation
// (gltf_export_animation.cc) and the meshes with their skins
// (gltf_export_mesh.cc). Private to engine/src/io (io/gltf and the demo character).
#pragma once

#include <cstdint>
#include <cstring>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <tiny_gltf.h>

#include "armature/engine/anim/clip.h"
#include "armature/engine/mesh/mesh.h"
#include "armature/base/status.h"

namespace armature::gltf_export {

// Bytes of JSON the writer may spend per node, accessor, channel … (names
// come on top): the estimate's allowance for everything but the buffer.
inline constexpr uint64_t kJsonBytesPerObject = 400;

// a + b and a · b saturating at UINT64_MAX, for the size estimate.
uint64_t Add(uint64_t a, uint64_t b);
uint64_t Mul(uint64_t a, uint64_t b);

// The float glTF stores for `x`: INVALID_ARGUMENT naming `where` when x is
// not finite or beyond the float range.
StatusOr<float> ToFloat(double x, const std::string& where);

class ModelBuilder {
 public:
  explicit ModelBuilder(uint64_t reserve_bytes = 0, const char* generator = "Armature");

  // Appends `values` as a bufferView (4-byte aligned) and an accessor of
  // `count` elements of `type` over it; returns the accessor.
  template <class T>
  int Add(std::span<const T> values, int component, int type, size_t count, int target = 0,
          std::vector<double> min = {}, std::vector<double> max = {}) {
    std::vector<unsigned char>& bin = model_.buffers[0].data;
    while (bin.size() % 4) bin.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = bin.size();
    view.byteLength = values.size() * sizeof(T);
    view.target = target;
    bin.resize(bin.size() + view.byteLength);
    if (view.byteLength) std::memcpy(bin.data() + view.byteOffset, values.data(), view.byteLength);
    model_.bufferViews.push_back(view);
    tinygltf::Accessor accessor;
    accessor.bufferView = static_cast<int>(model_.bufferViews.size()) - 1;
    accessor.componentType = component;
    accessor.type = type;
    accessor.count = count;
    accessor.minValues = std::move(min);
    accessor.maxValues = std::move(max);
    model_.accessors.push_back(std::move(accessor));
    return static_cast<int>(model_.accessors.size()) - 1;
  }
  template <class T>
  int Add(const std::vector<T>& values, int component, int type, size_t count, int target = 0,
          std::vector<double> min = {}, std::vector<double> max = {}) {
    return Add(std::span<const T>(values), component, type, count, target, std::move(min), std::move(max));
  }
  int AddFloats(std::span<const float> values, int type, size_t count, int target = 0) {
    return Add(values, TINYGLTF_COMPONENT_TYPE_FLOAT, type, count, target);
  }
  // Appends raw bytes (an image) as a bufferView with no target; returns it.
  int AddBytes(std::string_view bytes) {
    std::vector<unsigned char>& bin = model_.buffers[0].data;
    while (bin.size() % 4) bin.push_back(0);
    tinygltf::BufferView view;
    view.buffer = 0;
    view.byteOffset = bin.size();
    view.byteLength = bytes.size();
    bin.insert(bin.end(), bytes.begin(), bytes.end());
    model_.bufferViews.push_back(view);
    return static_cast<int>(model_.bufferViews.size()) - 1;
  }
  // Key times as a float accessor with min and max (glTF requires them on
  // sampler inputs), shared by the tracks that have the same times.
  StatusOr<int> AddTimes(const std::vector<double>& times, const std::string& where);

  tinygltf::Model& model() { return model_; }
  StatusOr<std::string> Write(bool binary);

 private:
  tinygltf::Model model_;
  std::map<std::vector<double>, int> times_;
};

// The skeleton as nodes 0..n-1 and the scene of its roots.
void AddSkeletonNodes(const Skeleton& skeleton, tinygltf::Model& model);

// The meshes, each with its skin, on nodes of the skeleton; returns, per
// mesh, the node that holds it (for weights channels).
StatusOr<std::vector<int>> AddMeshes(std::span<const Mesh* const> meshes, const Skeleton& skeleton,
                                     ModelBuilder& builder);
uint64_t MeshByteEstimate(const Mesh& mesh);

// Materials with their textures, samplers and images, each written once.
class MaterialWriter {
 public:
  explicit MaterialWriter(ModelBuilder& builder) : builder_(builder) {}
  int Add(const Material& material);  // the glTF material index

 private:
  int AddTexture(const TextureRef& ref, const Material& material);  // -1 when absent
  int AddImage(const MaterialImage& image);
  int AddSampler(const TextureSampler& sampler);

  ModelBuilder& builder_;
  std::map<const Material*, int> materials_;
  std::map<const MaterialImage*, int> images_;
};
// Buffer bytes of the meshes' UVs and distinct images; adds their JSON to `json`.
uint64_t MaterialByteEstimate(std::span<const Mesh* const> meshes, uint64_t* json);

// The clip as one animation. `mesh_nodes` maps a mesh's name to its node;
// weights tracks of meshes not written are dropped.
Status AddAnimation(const Clip& clip, const std::string& name, const std::map<std::string, int>& mesh_nodes,
                    ModelBuilder& builder);
uint64_t AnimationByteEstimate(const Clip& clip);

}  // namespace armature::gltf_export
