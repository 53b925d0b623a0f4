#include "armature/engine/anim/cubic_tangents.h"

#include "armature/engine/math/rotation.h"

namespace armature {
namespace {

template <class V, class Coeffs>
void Fill(std::span<const double> times, size_t n, const Coeffs& coeffs, std::vector<V>& in, std::vector<V>& out,
          const V& zero) {
  in.assign(n, zero);
  if (n >= 2)
    for (size_t k = 0; k < n; ++k) in[k] = KeyTangent<V>(times, coeffs, k);
  out = in;
}

}  // namespace

void FillCubicTangents(Vec3Track& track) {
  const size_t n = track.values.size();
  Fill<Eigen::Vector3d>(
      track.times, n, [&](size_t k) { return track.values[k]; }, track.in_tangents, track.out_tangents,
      Eigen::Vector3d::Zero());
}

void FillCubicTangents(QuatTrack& track) {
  const size_t n = track.values.size();
  for (size_t k = 1; k < n; ++k) track.values[k] = SameHemisphere(track.values[k], track.values[k - 1]);
  std::vector<Eigen::Vector4d> in, out;
  Fill<Eigen::Vector4d>(
      track.times, n, [&](size_t k) { return Eigen::Vector4d(track.values[k].coeffs()); }, in, out,
      Eigen::Vector4d::Zero());
  track.in_tangents.resize(n);
  track.out_tangents.resize(n);
  for (size_t k = 0; k < n; ++k) {
    track.in_tangents[k] = Eigen::Quaterniond(in[k]);  // coeffs order x, y, z, w, as the values
    track.out_tangents[k] = Eigen::Quaterniond(out[k]);
  }
}

}  // namespace armature
