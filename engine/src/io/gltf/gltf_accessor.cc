#include "gltf_accessor.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <optional>
#include <type_traits>

#include <tiny_gltf.h>

namespace armature::gltf_internal {

namespace {

// a·b + c, or nullopt when it does not fit 64 bits.
std::optional<uint64_t> MulAdd(uint64_t a, uint64_t b, uint64_t c) {
  uint64_t r;
  if (__builtin_mul_overflow(a, b, &r) || __builtin_add_overflow(r, c, &r)) return std::nullopt;
  return r;
}

size_t ComponentBytes(int component_type) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return 1;
    case TINYGLTF_COMPONENT_TYPE_SHORT:
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return 2;
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT:
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return 4;
    default: return 0;
  }
}

std::string ComponentTypeName(int t) {
  switch (t) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
    default: return std::to_string(t);
  }
}

size_t Components(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return 1;
    case TINYGLTF_TYPE_VEC2: return 2;
    case TINYGLTF_TYPE_VEC3: return 3;
    case TINYGLTF_TYPE_VEC4: return 4;
    case TINYGLTF_TYPE_MAT2: return 4;
    case TINYGLTF_TYPE_MAT3: return 9;
    case TINYGLTF_TYPE_MAT4: return 16;
    default: return 0;
  }
}

// One component at `p`, as its exact value or normalized per the spec.
double Component(const unsigned char* p, int component_type, bool normalize) {
  switch (component_type) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: {
      int8_t v;
      std::memcpy(&v, p, 1);
      return normalize ? std::max(v / 127.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return normalize ? p[0] / 255.0 : p[0];
    case TINYGLTF_COMPONENT_TYPE_SHORT: {
      int16_t v;
      std::memcpy(&v, p, 2);
      return normalize ? std::max(v / 32767.0, -1.0) : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: {
      uint16_t v;
      std::memcpy(&v, p, 2);
      return normalize ? v / 65535.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: {
      uint32_t v;
      std::memcpy(&v, p, 4);
      return normalize ? v / 4294967295.0 : v;
    }
    case TINYGLTF_COMPONENT_TYPE_FLOAT: {
      float v;
      std::memcpy(&v, p, 4);
      return v;
    }
    default: return 0;
  }
}

// The bytes of bufferView `view_index` starting at `offset`, checked to hold
// `count` elements of `element` bytes every `stride` bytes. `who` names the
// accessor and `offset_field` its offset's field, for the message.
StatusOr<const unsigned char*> ViewBytes(const tinygltf::Model& model, int view_index, uint64_t offset, uint64_t count,
                                         uint64_t element, uint64_t stride, const std::string& who,
                                         const char* offset_field) {
  if (view_index < 0 || static_cast<size_t>(view_index) >= model.bufferViews.size())
    return Status::InvalidArgument(who + " refers to bufferView " + std::to_string(view_index) + " (file has " +
                                   std::to_string(model.bufferViews.size()) + ")");
  const tinygltf::BufferView& view = model.bufferViews[static_cast<size_t>(view_index)];
  const std::string vwho = "bufferViews[" + std::to_string(view_index) + "]";
  if (view.buffer < 0 || static_cast<size_t>(view.buffer) >= model.buffers.size())
    return Status::InvalidArgument(vwho + " refers to buffer " + std::to_string(view.buffer) + " (file has " +
                                   std::to_string(model.buffers.size()) + ")");
  const tinygltf::Buffer& buffer = model.buffers[static_cast<size_t>(view.buffer)];
  if (view.byteOffset > buffer.data.size() || view.byteLength > buffer.data.size() - view.byteOffset)
    return Status::InvalidArgument(vwho + " (byteOffset " + std::to_string(view.byteOffset) + ", byteLength " +
                                   std::to_string(view.byteLength) + ") does not fit buffer " +
                                   std::to_string(view.buffer) + " of " + std::to_string(buffer.data.size()) +
                                   " bytes");
  if (stride < element)
    return Status::InvalidArgument(vwho + ": byteStride " + std::to_string(stride) + " is smaller than the " +
                                   std::to_string(element) + "-byte elements of " + who);
  if (offset > view.byteLength)
    return Status::InvalidArgument(who + " " + offset_field + " " + std::to_string(offset) +
                                   " is beyond the end of bufferView " + std::to_string(view_index) + " (" +
                                   std::to_string(view.byteLength) + " bytes)");
  if (count > 0) {
    // offset + (count − 1)·stride + element, each step checked for wrapping.
    const std::optional<uint64_t> needed = MulAdd(count - 1, stride, offset + element);
    if (!needed || *needed > view.byteLength)
      return Status::InvalidArgument(
          who + " needs " + (needed ? std::to_string(*needed) : std::string("more than 2^64")) +
          " bytes of bufferView " + std::to_string(view_index) + " but it has " + std::to_string(view.byteLength) +
          " (" + offset_field + " " + std::to_string(offset) + ", count " + std::to_string(count) + ", stride " +
          std::to_string(stride) + ")");
  }
  return buffer.data.data() + view.byteOffset + offset;
}

// The accessor's type and componentType are those the caller reads.
Status CheckAccessorKind(const tinygltf::Accessor& a, const std::string& who, AccessorType type,
                         std::initializer_list<int> component_types, bool float_allowed, bool normalize) {
  if (a.type != static_cast<int>(type))
    return Status::InvalidArgument(who + " has type " + AccessorTypeName(a.type) + ", expected " +
                                   AccessorTypeName(static_cast<int>(type)));
  const bool is_float = a.componentType == TINYGLTF_COMPONENT_TYPE_FLOAT;
  const bool listed =
      std::find(component_types.begin(), component_types.end(), a.componentType) != component_types.end();
  if (!(is_float && float_allowed) && !listed) {
    std::string expected = float_allowed ? "FLOAT" : "";
    for (int t : component_types) expected += (expected.empty() ? "" : " or ") + ComponentTypeName(t);
    return Status::InvalidArgument(who + " has componentType " + ComponentTypeName(a.componentType) + ", expected " +
                                   expected);
  }
  if (normalize && !is_float && !a.normalized)
    return Status::InvalidArgument(who + " has integer componentType " + ComponentTypeName(a.componentType) +
                                   " but is not normalized");
  if (a.count == 0) return Status::InvalidArgument(who + " has no elements");
  return Status::Ok();
}

// Sparse substitution: the listed elements replaced by the sparse values.
template <class T>
Status ApplySparse(const tinygltf::Model& model, const tinygltf::Accessor& a, const std::string& who, size_t components,
                   size_t bytes, bool convert, std::vector<T>& result) {
  const std::string swho = who + " sparse";
  const auto& s = a.sparse;
  const uint64_t element = components * bytes;
  if (s.count <= 0 || static_cast<size_t>(s.count) > a.count)
    return Status::InvalidArgument(swho + " count " + std::to_string(s.count) + " is not in [1, " +
                                   std::to_string(a.count) + "]");
  const int it = s.indices.componentType;
  if (it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
      it != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
    return Status::InvalidArgument(swho + " indices have componentType " + ComponentTypeName(it) +
                                   ", expected UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT");
  if (s.indices.byteOffset < 0 || s.values.byteOffset < 0)
    return Status::InvalidArgument(swho + " has a negative byteOffset");
  const uint64_t ib = ComponentBytes(it);
  ARMATURE_ASSIGN_OR_RETURN(const unsigned char* indices,
                            ViewBytes(model, s.indices.bufferView, static_cast<uint64_t>(s.indices.byteOffset),
                                      static_cast<uint64_t>(s.count), ib, ib, swho + " indices", "byteOffset"));
  ARMATURE_ASSIGN_OR_RETURN(
      const unsigned char* vals,
      ViewBytes(model, s.values.bufferView, static_cast<uint64_t>(s.values.byteOffset), static_cast<uint64_t>(s.count),
                element, element, swho + " values", "byteOffset"));
  double previous = -1;
  for (int k = 0; k < s.count; ++k) {
    const double target = Component(indices + static_cast<size_t>(k) * ib, it, false);
    if (target >= static_cast<double>(a.count) || target <= previous)
      return Status::InvalidArgument(swho + " index " + std::to_string(static_cast<uint64_t>(target)) + " at " +
                                     std::to_string(k) + " is out of range or not increasing");
    previous = target;
    const size_t i = static_cast<size_t>(target);
    for (size_t c = 0; c < components; ++c)
      result[i * components + c] =
          static_cast<T>(Component(vals + static_cast<size_t>(k) * element + c * bytes, a.componentType, convert));
  }
  return Status::Ok();
}

}  // namespace

std::string AccessorTypeName(int type) {
  switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return std::to_string(type);
  }
}

StatusOr<size_t> AccessorReader::Count(int index, const std::string& where) const {
  if (index < 0 || static_cast<size_t>(index) >= model_.accessors.size())
    return Status::InvalidArgument(where + ": accessor " + std::to_string(index) + " does not exist (file has " +
                                   std::to_string(model_.accessors.size()) + ")");
  return model_.accessors[static_cast<size_t>(index)].count;
}

StatusOr<uint64_t> AccessorReader::ChargeValues(const tinygltf::Accessor& a, const std::string& who) const {
  const size_t components = Components(a.type);
  const uint64_t element = components * ComponentBytes(a.componentType);
  if (a.bufferView < 0) {
    // No bufferView: zeros, unless sparse says otherwise. No bytes of the file
    // pay for these, so they have a cap of their own.
    const std::optional<uint64_t> unbacked = MulAdd(a.count, element, 0);
    if (!unbacked || *unbacked > limits_.max_unbacked_accessor_bytes)
      return Status::ResourceExhausted(
          who + " has no bufferView: " +
          OverImportLimit("count " + std::to_string(a.count) + " × " + std::to_string(element) + " bytes =",
                          unbacked.value_or(UINT64_MAX), "max_unbacked_accessor_bytes",
                          limits_.max_unbacked_accessor_bytes));
  }
  const std::optional<uint64_t> values = MulAdd(a.count, components, 0);
  const std::optional<uint64_t> total = values ? MulAdd(1, *values, values_read_) : std::nullopt;
  if (!total || *total > limits_.max_accessor_values)
    return Status::ResourceExhausted(
        who + ": " +
        OverImportLimit("count " + std::to_string(a.count) + " × " + std::to_string(components) +
                            " components, with the " + std::to_string(values_read_) + " values read before,",
                        total.value_or(UINT64_MAX), "max_accessor_values", limits_.max_accessor_values));
  return *total;
}

template <class T>
StatusOr<AccessorData> AccessorReader::Read(int index, const std::string& where, AccessorType type,
                                            std::initializer_list<int> component_types, bool float_allowed,
                                            bool normalize, std::vector<T>* out) const {
  if (index < 0 || static_cast<size_t>(index) >= model_.accessors.size())
    return Status::InvalidArgument(where + ": accessor " + std::to_string(index) + " does not exist (file has " +
                                   std::to_string(model_.accessors.size()) + ")");
  const tinygltf::Accessor& a = model_.accessors[static_cast<size_t>(index)];
  const std::string who = where + ": accessor " + std::to_string(index);
  ARMATURE_RETURN_IF_ERROR(CheckAccessorKind(a, who, type, component_types, float_allowed, normalize));
  const size_t components = Components(a.type);
  const size_t bytes = ComponentBytes(a.componentType);
  const uint64_t element = components * bytes;
  ARMATURE_ASSIGN_OR_RETURN(const uint64_t total, ChargeValues(a, who));
  const bool convert = normalize && a.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT;
  const size_t values = a.count * components;  // fits: ChargeValues checked it

  std::vector<T> result;
  if (a.bufferView >= 0) {
    const uint64_t stride = static_cast<size_t>(a.bufferView) < model_.bufferViews.size() &&
                                    model_.bufferViews[static_cast<size_t>(a.bufferView)].byteStride
                                ? model_.bufferViews[static_cast<size_t>(a.bufferView)].byteStride
                                : element;
    ARMATURE_ASSIGN_OR_RETURN(const unsigned char* data, ViewBytes(model_, a.bufferView, a.byteOffset, a.count, element,
                                                                   stride, who, "byteOffset"));
    result.resize(values);
    for (size_t i = 0; i < a.count; ++i)
      for (size_t c = 0; c < components; ++c)
        result[i * components + c] = static_cast<T>(Component(data + i * stride + c * bytes, a.componentType, convert));
  } else {
    result.assign(values, T{});
  }
  values_read_ = total;
  if (a.sparse.isSparse) ARMATURE_RETURN_IF_ERROR(ApplySparse(model_, a, who, components, bytes, convert, result));
  if constexpr (std::is_floating_point_v<T>) {
    for (size_t i = 0; i < result.size(); ++i)
      if (!std::isfinite(result[i]))
        return Status::InvalidArgument(who + " element " + std::to_string(i / components) + " is not finite");
  }
  *out = std::move(result);
  return AccessorData{a.count, components};
}

StatusOr<AccessorData> AccessorReader::ReadFloats(int index, const std::string& where, AccessorType type,
                                                  std::initializer_list<int> normalized_types,
                                                  std::vector<float>* out) const {
  return Read(index, where, type, normalized_types, true, true, out);
}

StatusOr<AccessorData> AccessorReader::ReadUints(int index, const std::string& where, AccessorType type,
                                                 std::initializer_list<int> component_types,
                                                 std::vector<uint32_t>* out) const {
  return Read(index, where, type, component_types, false, false, out);
}

}  // namespace armature::gltf_internal
