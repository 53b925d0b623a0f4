// Hostile uploads for the server to refuse: random bytes under every
// extension, truncated and bit-flipped real files, and "bombs" (small files
// that claim huge sizes). Deterministic for a seed.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace armature::testing {

struct HostileUpload {
  std::string kind;      // "random", "truncated", "bitflip" or "bomb:<shape>", for the report
  std::string filename;  // with the extension the server sees
  std::string bytes;
};

// The bombs, one of each shape.
std::vector<HostileUpload> BombUploads();

// `count` uploads: bombs spread evenly through random and mutated files.
std::vector<HostileUpload> HostileUploads(int count, uint32_t seed);

}  // namespace armature::testing
