// Internal: reading glTF accessors with every index, bound and type checked,
// so a malformed file gets an error naming the field and accessor instead of
// an out-of-bounds read.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <string>
#include <vector>

#include "armature/engine/io/import_limits.h"
#include "armature/base/status.h"

namespace tinygltf {
class Model;
struct Accessor;
}  // namespace tinygltf

namespace armature::gltf_internal {

// glTF accessor types ("SCALAR", "VEC3", …) as tinygltf numbers them.
enum class AccessorType { kScalar = 65, kVec2 = 2, kVec3 = 3, kVec4 = 4, kMat4 = 36 };

struct AccessorData {
  size_t count = 0;       // elements
  size_t components = 0;  // per element
};

// Keeps count of the values it decodes: past limits.max_accessor_values in
// all, further reads are RESOURCE_EXHAUSTED.
class AccessorReader {
 public:
  AccessorReader(const tinygltf::Model& model, const ImportLimits& limits) : model_(model), limits_(limits) {}

  // The element count of accessor `index` (checked to exist), without reading
  // it: lets callers bound what they will build before decoding.
  StatusOr<size_t> Count(int index, const std::string& where) const;

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
  // Validates the accessor (every bound in overflow-checked arithmetic) and
  // returns its elements (integers exact), normalized when `normalize` is set.
  template <class T>
  StatusOr<AccessorData> Read(int index, const std::string& where, AccessorType type,
                              std::initializer_list<int> component_types, bool float_allowed, bool normalize,
                              std::vector<T>* out) const;

  // The values read so far with accessor `a`'s: RESOURCE_EXHAUSTED past
  // max_accessor_values, or for an accessor without a bufferView past
  // max_unbacked_accessor_bytes.
  StatusOr<uint64_t> ChargeValues(const tinygltf::Accessor& a, const std::string& who) const;

  const tinygltf::Model& model_;
  const ImportLimits& limits_;
  mutable uint64_t values_read_ = 0;
};

std::string AccessorTypeName(int type);

}  // namespace armature::gltf_internal
