// A cycle in an FBX file's object-to-object connections ("C: "OO", child,
// parent") sends assimp's node conversion into endless recursion, which
// overflows the stack and ends the process (found by fuzz.engine_fbx_fuzz).
// Real files connect objects as a tree or a DAG, so the bytes are scanned for
// those connections, ASCII or binary, and a cycle is refused before assimp
// sees them. Every walk here is iterative and bounded by the bytes.
#include <cstdint>
#include <cstring>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "fbx_importer.h"

namespace armature::fbx_internal {

namespace {

using Edges = std::vector<std::pair<int64_t, int64_t>>;  // child → parent

constexpr std::string_view kBinaryMagic("Kaydara FBX Binary  \0", 21);

// `C: "OO",child,parent` lines anywhere in an ASCII file.
Edges AsciiConnections(std::string_view text) {
  Edges edges;
  for (size_t at = text.find("\"OO\""); at != std::string_view::npos; at = text.find("\"OO\"", at + 4)) {
    size_t i = at + 4;
    int64_t ids[2] = {0, 0};
    bool ok = true;
    for (int64_t& id : ids) {
      while (i < text.size() && (text[i] == ' ' || text[i] == '\t' || text[i] == ',')) ++i;
      const bool negative = i < text.size() && text[i] == '-';
      if (negative) ++i;
      const size_t first = i;
      uint64_t v = 0;
      while (i < text.size() && text[i] >= '0' && text[i] <= '9' && i - first < 19) v = 10 * v + (text[i++] - '0');
      if (i == first) ok = false;
      id = negative ? -static_cast<int64_t>(v) : static_cast<int64_t>(v);
    }
    if (ok) edges.emplace_back(ids[0], ids[1]);
  }
  return edges;
}

template <typename T>
bool ReadLe(std::string_view bytes, size_t at, T& out) {
  if (at > bytes.size() || bytes.size() - at < sizeof(T)) return false;
  std::memcpy(&out, bytes.data() + at, sizeof(T));  // FBX is little-endian, as x86 and arm64 are
  return true;
}

// A binary "C" record's properties: 'S' "OO", then two 'L' ids.
void BinaryConnection(std::string_view props, Edges& edges) {
  uint32_t length = 0;
  if (props.empty() || props[0] != 'S' || !ReadLe(props, 1, length) || length != 2 || props.size() < 7 ||
      props.substr(5, 2) != "OO")
    return;
  int64_t ids[2];
  size_t at = 7;
  for (int64_t& id : ids) {
    if (at >= props.size() || props[at] != 'L' || !ReadLe(props, at + 1, id)) return;
    at += 9;
  }
  edges.emplace_back(ids[0], ids[1]);
}

// Every "C" record in a binary file, at any depth, walked with a stack of
// the enclosing records' ends.
Edges BinaryConnections(std::string_view bytes) {
  Edges edges;
  uint32_t version = 0;
  if (!ReadLe(bytes, 23, version)) return edges;
  const bool wide = version >= 7500;
  const size_t header = wide ? 25 : 13;
  std::vector<size_t> ends = {bytes.size()};
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
    if (std::string_view(bytes.data() + at + header, name_length) == "C")
      BinaryConnection(bytes.substr(props_at, props_length), edges);
    const size_t children = props_at + props_length;
    if (children < end) {
      ends.push_back(end);
      at = children;
    } else {
      at = end;
    }
  }
  return edges;
}

}  // namespace

Status CheckConnectionsAcyclic(std::string_view bytes) {
  const Edges edges =
      bytes.substr(0, kBinaryMagic.size()) == kBinaryMagic ? BinaryConnections(bytes) : AsciiConnections(bytes);
  std::map<int64_t, std::vector<int64_t>> parents;
  for (const auto& [child, parent] : edges) parents[child].push_back(parent);
  // Iterative depth-first search: 1 = on the current path, 2 = done.
  std::map<int64_t, int> state;
  for (const auto& [start, unused] : parents) {
    if (state[start] != 0) continue;
    std::vector<std::pair<int64_t, size_t>> path = {{start, 0}};
    state[start] = 1;
    while (!path.empty()) {
      auto& [id, next] = path.back();
      const auto it = parents.find(id);
      if (it == parents.end() || next == it->second.size()) {
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

}  // namespace armature::fbx_internal
