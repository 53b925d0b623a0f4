#include "armature/engine/io/asset.h"

#include <algorithm>
#include <cctype>
#include <memory>
#include <string>

#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/io/fbx/fbx.h"
#include "armature/engine/io/gltf/gltf.h"
#include "armature/engine/io/obj/obj.h"
#include "armature/base/utf8.h"

namespace armature {

std::string_view FormatName(AssetFormat f) {
  switch (f) {
    case AssetFormat::kBvh: return "bvh";
    case AssetFormat::kGltf: return "gltf";
    case AssetFormat::kGlb: return "glb";
    case AssetFormat::kObj: return "obj";
    case AssetFormat::kFbx: return "fbx";
  }
  return "?";
}

std::string_view FormatExtension(AssetFormat f) {
  switch (f) {
    case AssetFormat::kBvh: return ".bvh";
    case AssetFormat::kGltf: return ".gltf";
    case AssetFormat::kGlb: return ".glb";
    case AssetFormat::kObj: return ".obj";
    case AssetFormat::kFbx: return ".fbx";
  }
  return "";
}

namespace {

std::string Lower(std::string_view s) {
  std::string r(s);
  std::transform(r.begin(), r.end(), r.begin(), [](unsigned char c) { return std::tolower(c); });
  return r;
}

std::optional<AssetFormat> FromName(std::string_view name) {
  const std::string n = Lower(name);
  for (AssetFormat f : {AssetFormat::kBvh, AssetFormat::kGltf, AssetFormat::kGlb, AssetFormat::kObj, AssetFormat::kFbx})
    if (n == FormatName(f)) return f;
  return std::nullopt;
}

}  // namespace

StatusOr<AssetFormat> DetectFormat(std::string_view explicit_format, std::string_view filename,
                                   std::string_view bytes) {
  if (!explicit_format.empty()) {
    if (auto f = FromName(explicit_format)) return *f;
    return Status::InvalidArgument("format: unknown format '" + EscapeForMessage(explicit_format) +
                                   "' (expected bvh, gltf, glb, obj or fbx)");
  }
  if (auto dot = filename.rfind('.'); dot != std::string_view::npos)
    if (auto f = FromName(filename.substr(dot + 1))) return *f;
  // Content sniffing.
  if (bytes.size() >= 4 && bytes.substr(0, 4) == "glTF") return AssetFormat::kGlb;
  if (LooksLikeFbx(bytes)) return AssetFormat::kFbx;
  size_t i = 0;
  while (i < bytes.size() && std::isspace(static_cast<unsigned char>(bytes[i]))) ++i;
  const std::string_view rest = bytes.substr(i);
  if (rest.substr(0, 9) == "HIERARCHY") return AssetFormat::kBvh;
  if (!rest.empty() && rest[0] == '{' && rest.substr(0, 4096).find("\"asset\"") != std::string_view::npos)
    return AssetFormat::kGltf;
  if (rest.substr(0, 2) == "v " || rest.substr(0, 1) == "#" || rest.substr(0, 2) == "o ") return AssetFormat::kObj;
  return Status::InvalidArgument("cannot tell the file's format from its name '" + EscapeForMessage(filename) +
                                 "' or content; pass format (bvh, gltf, glb, obj or fbx)");
}

std::string OverImportLimit(const std::string& what, uint64_t value, const char* field, uint64_t limit) {
  return what + " " + std::to_string(value) + " is over the import limit " + field + " = " + std::to_string(limit);
}

std::string OverImportLimitCount(uint64_t value, const std::string& unit, const char* field, uint64_t limit) {
  return std::to_string(value) + " " + unit + " is over the import limit " + field + " = " + std::to_string(limit);
}

Status ChargeDecodedBytes(uint64_t* total, uint64_t bytes, const ImportLimits& limits, const std::string& where) {
  if (__builtin_add_overflow(*total, bytes, total)) *total = UINT64_MAX;
  if (*total > limits.max_decoded_bytes)
    return Status::ResourceExhausted(where + ": " +
                                     OverImportLimit("the estimated memory of the parts decoded so far,", *total,
                                                     "max_decoded_bytes", limits.max_decoded_bytes) +
                                     " bytes");
  return Status::Ok();
}

namespace {

StatusOr<AssetContents> ParseFormat(AssetFormat format, std::string_view bytes, std::string_view name,
                                    const ResourceMap& resources, const ImportLimits& limits) {
  switch (format) {
    case AssetFormat::kBvh: {
      ARMATURE_ASSIGN_OR_RETURN(auto bvh, ParseBvh(bytes, limits));
      AssetContents c;
      c.skeletons.push_back({std::string(name), bvh.skeleton});
      c.clips.push_back({std::string(name), std::string(name), bvh.clip});
      c.warnings = std::move(bvh.warnings);
      return c;
    }
    case AssetFormat::kGltf:
    case AssetFormat::kGlb: return ParseGltf(bytes, format == AssetFormat::kGlb, name, resources, limits);
    case AssetFormat::kObj: {
      AssetContents c;
      ARMATURE_ASSIGN_OR_RETURN(auto mesh, ParseObj(bytes, name, &c.warnings, limits));
      c.meshes.push_back({std::string(name), "", std::make_shared<const Mesh>(std::move(mesh))});
      return c;
    }
    case AssetFormat::kFbx: return ParseFbx(bytes, name, limits);
  }
  return Status::InvalidArgument("unknown asset format " + std::to_string(static_cast<int>(format)));
}

}  // namespace

StatusOr<AssetContents> ParseAsset(AssetFormat format, std::string_view bytes, std::string_view name,
                                   const ResourceMap& resources, const ImportLimits& limits) {
  // The parsers return a Status for any bytes; this boundary only keeps a
  // failed allocation or a bug in a third-party parser from escaping into the
  // caller's thread.
  try {
    return ParseFormat(format, bytes, name, resources, limits);
  } catch (const std::bad_alloc&) {
    return Status::ResourceExhausted("out of memory while importing the file");
  } catch (const std::exception& e) {
    return Status::Internal("import failed: " + EscapeForMessage(e.what(), 200));
  }
}

}  // namespace armature
