// Internal: reading glTF accessors with every index, bound and type checked,
// so a malformed file gets an error naming the field and accessor instead of
// an out-of-bounds read.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "armature/engine/status.h"

namespace tinygltf {
class Model;
}

namespace armature::gltf_internal {

// glTF accessor types ("SCALAR", "VEC3", …) as tinygltf numbers them.
enum class AccessorType { kScalar = 65, kVec2 = 2, kVec3 = 3, kVec4 = 4, kMat4 = 36 };

struct AccessorData {
  size_t count = 0;       // elements
  size_t components = 0;  // per element
};

class AccessorReader {
 public:
  explicit AccessorReader(const tinygltf::Model& model) : model_(model) {}

  // Floats: FLOAT components as they are; integer components only when the
  // accessor is normalized (and their type is in `normalized_types`),
  // converted as the spec says (e.g. UNSIGNED_BYTE c → c/255). Values must be
  // finite. `where` names the field, e.g. "meshes[0].primitives[0].attributes.WEIGHTS_0".
  StatusOr<AccessorData> ReadFloats(int index, const std::string& where, AccessorType type,
                                    std::initializer_list<int> normalized_types, std::vector<float>* out) const;

  // Unsigned integers (indices, joints) of the listed component types.
  StatusOr<AccessorData> ReadUints(int index, const std::string& where, AccessorType type,
                                   std::initializer_list<int> component_types, std::vector<uint32_t>* out) const;

 private:
  // Validates the accessor and returns its elements as raw doubles (integers
  // exact), normalized when `normalize` is set.
  StatusOr<AccessorData> Read(int index, const std::string& where, AccessorType type,
                              std::initializer_list<int> component_types, bool float_allowed, bool normalize,
                              std::vector<double>* out) const;

  const tinygltf::Model& model_;
};

std::string AccessorTypeName(int type);

}  // namespace armature::gltf_internal
