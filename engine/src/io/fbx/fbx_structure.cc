// What assimp would choke on, found in the bytes before assimp reads them.
//
// Recursion. assimp reads an FBX file recursively: its scopes (ASCII
// braces, binary records nested in records) and then its object
// connections ("C: "OO", child, parent", or any type but "PP") from the
// root down. A cycle in the connections recursed without end (found by
// fuzz.engine_fbx_fuzz), and a chain of 10,000 connected objects or 30,000
// nested scopes overflowed an 8 MB stack: each ended the process. Real
// files nest a few levels and connect objects as a tree or a DAG a few
// dozen deep, so a cycle or a depth over kMaxDepth is refused.
//
// Objects sharing an id. assimp keeps the last object of an id and leaks
// the others (40 bytes each, for good, even when the import succeeds;
// found by fuzz.engine_fbx_fuzz). Ids are unique in a file any exporter
// writes, so a repeated one is refused.
//
// Arrays inflated. A binary file's arrays may be deflated, and assimp
// inflates each it reads to the count the array declares: a 1.6 MB file
// of deflated zeros declaring 201 M doubles took 2.4 GB in the reader. The
// declared counts times their element sizes are summed over the file,
// and a sum over the import limit max_decoded_bytes is refused.
//
// The bytes are scanned, ASCII or binary, by iterative walks bounded by
// the bytes.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "armature/base/utf8.h"
#include "fbx_importer.h"

namespace armature::fbx_internal {

namespace {

using Edges = std::vector<std::pair<int64_t, int64_t>>;  // child → parent

// An object's id, and where it is: the line of an ASCII file, the byte
// offset of a binary one.
struct ObjectId {
  int64_t id;
  size_t where;
};

// Scopes nested, or objects chained, deeper than this are refused: about
// 1 MB of assimp's stack at the deepest (a connection level takes about
// 1 KB of it in the release build, a scope about 300 bytes).
constexpr size_t kMaxDepth = 1000;

// A binary file's arrays, as assimp would inflate them.
struct Arrays {
  uint64_t inflated = 0;  // bytes of all of them (saturating)
  uint64_t largest = 0, largest_stored = 0;
  size_t largest_at = 0;            // the byte offset of its record
  std::string_view largest_record;  // its name, in the scanned bytes
};

// What assimp would recurse through: the connections, and how deep the
// scopes nest; and what its arrays would take.
struct Structure {
  Edges edges;
  size_t depth = 0;
  std::vector<ObjectId> objects;  // the ids of the top-level "Objects" scope's children
  Arrays arrays;
};

constexpr std::string_view kBinaryMagic("Kaydara FBX Binary  \0", 21);

// A connection's type: assimp skips "PP" and links every other type as
// objects ("OP" adds a property name, which node conversion skips), so a
// mistyped "OxglO" links them too (found by fuzz.engine_fbx_fuzz).
bool LinksObjects(std::string_view type) { return type != "PP"; }

bool IsSpace(char c) { return c == ' ' || c == '\t' || c == '\r' || c == '\n'; }

// What ends a token in assimp's ASCII tokenizer.
bool EndsToken(char c) { return IsSpace(c) || c == ',' || c == '{' || c == '}' || c == ';' || c == ':' || c == '"'; }

// A token's leading digits from `i` on, as assimp's strtoul10_64 reads
// them: an overflow it notices (the new value below the old) is 0, one it
// misses wraps. `i` ends past them; false when there are none.
bool ReadDigits(std::string_view text, size_t& i, uint64_t& value) {
  const size_t first = i;
  bool overflowed = false;
  value = 0;
  for (; i < text.size() && text[i] >= '0' && text[i] <= '9'; ++i) {
    const uint64_t next = value * 10 + static_cast<uint64_t>(text[i] - '0');
    overflowed = overflowed || next < value;
    value = next;
  }
  if (overflowed) value = 0;
  return i > first;
}

// `C: "type",child,parent` records anywhere in an ASCII file (a record's
// tokens may run over lines).
Edges AsciiConnections(std::string_view text) {
  Edges edges;
  // Each record is read past once (a quoted type ending far away holds
  // any "C:" before its end), so the scan stays linear in the bytes.
  for (size_t at = text.find("C:"); at != std::string_view::npos; at = text.find("C:", at)) {
    size_t i = at + 2;
    const bool starts_token = at == 0 || IsSpace(text[at - 1]) || text[at - 1] == '{' || text[at - 1] == '}';
    at = i;
    if (!starts_token) continue;
    while (i < text.size() && IsSpace(text[i])) ++i;
    if (i >= text.size() || text[i] != '"') continue;
    const size_t type_end = text.find('"', i + 1);
    if (type_end == std::string_view::npos) break;
    at = type_end + 1;
    if (!LinksObjects(text.substr(i + 1, type_end - i - 1))) continue;
    i = type_end + 1;
    int64_t ids[2] = {0, 0};
    bool ok = true;
    for (int64_t& id : ids) {
      while (i < text.size() && (IsSpace(text[i]) || text[i] == ',')) ++i;
      const bool negative = i < text.size() && text[i] == '-';
      if (negative) ++i;
      uint64_t v = 0;
      if (!ReadDigits(text, i, v)) ok = false;
      id = negative ? -static_cast<int64_t>(v) : static_cast<int64_t>(v);
      // assimp reads a token's leading digits as its id and ignores the
      // rest ("3000-0" is 3000), so the next id starts at the next token
      // (found by fuzz.engine_fbx_fuzz: "3000-0" read as 3000 and then 0
      // hid a cycle).
      while (i < text.size() && !EndsToken(text[i])) ++i;
    }
    at = i;
    if (ok) edges.emplace_back(ids[0], ids[1]);
  }
  return edges;
}

// An ASCII file's scopes, walked as assimp's tokenizer reads them (quoted
// strings and comments, ';' to the end of the line, hold no braces): how
// deep its braces nest, and the ids of its objects. Each child of the first
// top-level "Objects" scope, keyed "Type:", has its first data token as its
// id (assimp reads the token's leading digits; one without digits fails
// the read, so it is left out here).
void AsciiScopes(std::string_view text, Structure& structure) {
  enum { kBefore, kKeyRead, kInside, kDone } objects = kBefore;
  size_t depth = 0, line = 1, key_line = 0;
  bool want_id = false;  // a child's key was just read
  for (size_t i = 0; i < text.size();) {
    const char c = text[i];
    if (IsSpace(c) || c == ',' || c == ':') {
      line += c == '\n';
      ++i;
      continue;
    }
    if (c == ';') {  // a comment, to the end of the line
      i = text.find('\n', i);
      continue;  // npos ends the loop
    }
    if (c == '{' || c == '}') {
      if (c == '{') objects = objects == kKeyRead && depth == 0 ? kInside : objects;
      depth = c == '{' ? depth + 1 : depth - (depth > 0);
      structure.depth = std::max(structure.depth, depth);
      if (objects == kInside && depth == 0) objects = kDone;
      want_id = false;
      ++i;
      continue;
    }
    const size_t start = i;
    if (c == '"') {
      const size_t end = text.find('"', i + 1);
      if (end == std::string_view::npos) break;
      line += static_cast<size_t>(std::count(text.begin() + i, text.begin() + end, '\n'));
      i = end + 1;
    } else {
      while (i < text.size() && !EndsToken(text[i])) ++i;
    }
    const std::string_view token = text.substr(start, i - start);
    if (i < text.size() && text[i] == ':' && c != '"') {  // a key
      if (depth == 0 && objects == kBefore && token == "Objects") {
        objects = kKeyRead;
      } else if (depth == 0 && objects == kKeyRead) {
        objects = kDone;  // "Objects" without a scope: assimp refuses the file
      }
      want_id = objects == kInside && depth == 1;
      key_line = line;
      continue;
    }
    size_t digit = 0;
    uint64_t id = 0;
    if (want_id && ReadDigits(token, digit, id)) structure.objects.push_back({static_cast<int64_t>(id), key_line});
    want_id = false;
  }
}

template <typename T>
bool ReadLe(std::string_view bytes, size_t at, T& out) {
  if (at > bytes.size() || bytes.size() - at < sizeof(T)) return false;
  std::memcpy(&out, bytes.data() + at, sizeof(T));  // FBX is little-endian, as x86 and arm64 are
  return true;
}

// A binary "C" record's properties: 'S' and its type, then two 'L' ids.
void BinaryConnection(std::string_view props, Edges& edges) {
  uint32_t length = 0;
  if (props.empty() || props[0] != 'S' || !ReadLe(props, 1, length) || props.size() - 5 < length ||
      !LinksObjects(props.substr(5, length)))
    return;
  int64_t ids[2];
  size_t at = 5 + size_t{length};
  for (int64_t& id : ids) {
    if (at >= props.size() || props[at] != 'L' || !ReadLe(props, at + 1, id)) return;
    at += 9;
  }
  edges.emplace_back(ids[0], ids[1]);
}

// The bytes one element of a binary array property takes ('f', 'd', 'l',
// 'i', 'b'), or 0 for a property of another type.
uint64_t ArrayElementBytes(char type) {
  switch (type) {
    case 'b': return 1;
    case 'f':
    case 'i': return 4;
    case 'd':
    case 'l': return 8;
    default: return 0;
  }
}

// The bytes a scalar property takes after its type, or -1 for an unknown type.
int ScalarBytes(char type) {
  switch (type) {
    case 'C': return 1;
    case 'Y': return 2;
    case 'I':
    case 'F': return 4;
    case 'D':
    case 'L': return 8;
    default: return -1;
  }
}

// Adds the arrays among a binary record's properties (`props`, the record
// named `name` at byte `at`) to `arrays`. A property it cannot read ends
// the walk: assimp refuses the record for it.
void BinaryArrays(std::string_view props, std::string_view name, size_t at, Arrays& arrays) {
  for (size_t i = 0; i < props.size();) {
    const char type = props[i++];
    if (const uint64_t element = ArrayElementBytes(type)) {
      uint32_t count = 0, stored = 0;
      if (!ReadLe(props, i, count) || !ReadLe(props, i + 8, stored) || props.size() - (i + 12) < stored) return;
      const uint64_t inflated = uint64_t{count} * element;
      if (__builtin_add_overflow(arrays.inflated, inflated, &arrays.inflated)) arrays.inflated = UINT64_MAX;
      if (inflated > arrays.largest) arrays = {arrays.inflated, inflated, stored, at, name};
      i += 12 + size_t{stored};
    } else if (type == 'S' || type == 'R') {
      uint32_t length = 0;
      if (!ReadLe(props, i, length) || props.size() - (i + 4) < length) return;
      i += 4 + size_t{length};
    } else {
      const int bytes = ScalarBytes(type);
      if (bytes < 0) return;
      i += static_cast<size_t>(bytes);
    }
  }
}

// Every "C" record in a binary file, at any depth, how deep records nest,
// and the arrays, walked with a stack of the enclosing records' ends.
Structure BinaryStructure(std::string_view bytes) {
  Structure structure;
  Edges& edges = structure.edges;
  uint32_t version = 0;
  if (!ReadLe(bytes, 23, version)) return structure;
  const bool wide = version >= 7500;
  const size_t header = wide ? 25 : 13;
  std::vector<size_t> ends = {bytes.size()};
  size_t objects_end = 0;  // the end of the first top-level "Objects" record
  size_t at = 27;
  while (!ends.empty()) {
    if (at >= ends.back() || ends.back() - at < header) {  // this list is done
      at = ends.back();
      ends.pop_back();
      continue;
    }
    uint64_t end = 0, props_length = 0;
    if (wide) {
      ReadLe(bytes, at, end);
      ReadLe(bytes, at + 16, props_length);
    } else {
      uint32_t e = 0, p = 0;
      ReadLe(bytes, at, e);
      ReadLe(bytes, at + 8, p);
      end = e;
      props_length = p;
    }
    const auto name_length = static_cast<uint8_t>(bytes[at + header - 1]);
    if (end == 0) {  // the null record that ends a nested list
      at += header;
      continue;
    }
    const size_t props_at = at + header + name_length;
    if (end <= at || end > ends.back() || props_at > end || end - props_at < props_length) break;  // malformed
    const std::string_view name(bytes.data() + at + header, name_length);
    if (name == "C") BinaryConnection(bytes.substr(props_at, props_length), edges);
    BinaryArrays(bytes.substr(props_at, props_length), name, at, structure.arrays);
    if (ends.size() == 1 && objects_end == 0 && name == "Objects") objects_end = end;
    int64_t id = 0;
    if (ends.size() == 2 && ends.back() == objects_end && props_length >= 9 && bytes[props_at] == 'L' &&
        ReadLe(bytes, props_at + 1, id))
      structure.objects.push_back({id, at});
    const size_t children = props_at + props_length;
    if (children < end) {
      ends.push_back(end);
      structure.depth = std::max(structure.depth, ends.size() - 1);
      at = children;
    } else {
      at = end;
    }
  }
  return structure;
}

// INVALID_ARGUMENT for a cycle in the connections or a chain of them
// deeper than kMaxDepth: an iterative depth-first search, each object's
// chain length (itself and its deepest line of parents) set when it is done.
Status CheckConnections(const Edges& edges) {
  std::map<int64_t, std::vector<int64_t>> parents;
  for (const auto& [child, parent] : edges) parents[child].push_back(parent);
  std::map<int64_t, int> state;  // 1 = on the current path, 2 = done
  std::map<int64_t, size_t> chain;
  for (const auto& [start, unused] : parents) {
    if (state[start] != 0) continue;
    std::vector<std::pair<int64_t, size_t>> path = {{start, 0}};
    state[start] = 1;
    while (!path.empty()) {
      auto& [id, next] = path.back();
      const auto it = parents.find(id);
      if (it == parents.end() || next == it->second.size()) {
        size_t longest = 0;
        if (it != parents.end())
          for (const int64_t parent : it->second) longest = std::max(longest, chain[parent]);
        chain[id] = longest + 1;
        if (chain[id] > kMaxDepth)
          return Status::InvalidArgument("FBX: a chain of over " + std::to_string(kMaxDepth) +
                                         " connected objects (object " + std::to_string(id) +
                                         "), deeper than real files connect them");
        state[id] = 2;
        path.pop_back();
        continue;
      }
      const int64_t parent = it->second[next++];
      if (state[parent] == 1)
        return Status::InvalidArgument("FBX: the connections form a cycle (object " + std::to_string(id) +
                                       " is connected to " + std::to_string(parent) +
                                       ", which is among its own parents)");
      if (state[parent] == 0) {
        state[parent] = 1;
        path.emplace_back(parent, 0);
      }
    }
  }
  return Status::Ok();
}

// INVALID_ARGUMENT naming the first id two objects share.
Status CheckObjectIds(std::vector<ObjectId> objects, bool binary) {
  std::stable_sort(objects.begin(), objects.end(), [](const ObjectId& a, const ObjectId& b) { return a.id < b.id; });
  const auto same = std::adjacent_find(objects.begin(), objects.end(),
                                       [](const ObjectId& a, const ObjectId& b) { return a.id == b.id; });
  if (same == objects.end()) return Status::Ok();
  const char* where = binary ? "at bytes " : "on lines ";
  return Status::InvalidArgument("FBX: two objects share the id " + std::to_string(same->id) + " (" + where +
                                 std::to_string(same->where) + " and " + std::to_string(std::next(same)->where) +
                                 "); an object's id must be its own");
}

// RESOURCE_EXHAUSTED when the arrays inflated pass max_decoded_bytes.
Status CheckArrays(const Arrays& arrays, const ImportLimits& limits) {
  if (arrays.inflated <= limits.max_decoded_bytes) return Status::Ok();
  return Status::ResourceExhausted(
      "FBX: " +
      OverImportLimitCount(arrays.inflated, "bytes of arrays inflated", "max_decoded_bytes", limits.max_decoded_bytes) +
      " (the largest: \"" + EscapeForMessage(arrays.largest_record, 40) + "\" at byte " +
      std::to_string(arrays.largest_at) + ", " + std::to_string(arrays.largest) + " bytes from " +
      std::to_string(arrays.largest_stored) + " stored)");
}

}  // namespace

Status CheckStructure(std::string_view bytes, const ImportLimits& limits) {
  const bool binary = bytes.substr(0, kBinaryMagic.size()) == kBinaryMagic;
  Structure structure;
  if (binary) {
    structure = BinaryStructure(bytes);
  } else {
    structure.edges = AsciiConnections(bytes);
    AsciiScopes(bytes, structure);
  }
  if (structure.depth > kMaxDepth)
    return Status::InvalidArgument(std::string("FBX: ") + (binary ? "records" : "braces") + " nested " +
                                   std::to_string(structure.depth) + " deep, over the limit of " +
                                   std::to_string(kMaxDepth));
  ARMATURE_RETURN_IF_ERROR(CheckConnections(structure.edges));
  ARMATURE_RETURN_IF_ERROR(CheckObjectIds(structure.objects, binary));
  return CheckArrays(structure.arrays, limits);
}

}  // namespace armature::fbx_internal
