// BVH read → write → read: whatever the reader accepts, the writer writes and
// the reader reads back with the same joints and frames.
#include <cstdint>
#include <string_view>

#include "armature/engine/io/bvh/bvh.h"
#include "round_trip.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  using namespace armature;
  auto bvh = ParseBvh(std::string_view(reinterpret_cast<const char*>(data), size), fuzz::Limits());
  if (bvh.ok()) fuzz::ExpectBvhRoundTrip(*bvh->clip);
  return 0;
}
