// The tangents a CUBIC track without glTF tangents implies, so it can be
// stored as glTF CUBICSPLINE and stay C¹ through its keys.
#pragma once

#include <cstddef>
#include <span>

#include "armature/engine/anim/clip.h"

namespace armature {

// Slope at key i (units per second) of the parabola through keys i−1, i, i+1:
// Catmull-Rom's tangent made aware of uneven key spacing, one-sided at the
// ends. Needs at least two keys. CUBIC sampling of vectors uses it.
template <class V, class ValueAt>
V KeyTangent(std::span<const double> times, const ValueAt& value, size_t i) {
  const size_t n = times.size();
  if (i == 0) return (value(1) - value(0)) / (times[1] - times[0]);
  if (i == n - 1) return (value(n - 1) - value(n - 2)) / (times[n - 1] - times[n - 2]);
  const double hp = times[i] - times[i - 1], hn = times[i + 1] - times[i];
  const V dp = (value(i) - value(i - 1)) / hp, dn = (value(i + 1) - value(i)) / hn;
  return (dn * hp + dp * hn) / (hp + hn);
}

// Sets in = out = KeyTangent at every key of a CUBIC track that has no
// tangents: sampling then gives exactly what Catmull-Rom sampling gave.
// A single key gets zero tangents.
void FillCubicTangents(Vec3Track& track);

// For rotations: first flips each key to the hemisphere of the one before
// (the values change sign, never the rotations they are), then the same
// slopes on the quaternion components. The glTF CUBICSPLINE curve this gives
// (Hermite on components, normalized) is C¹ through the keys, as three.js's
// CubicInterpolant is; it is close to, not equal to, the squad that CUBIC
// sampling without tangents uses.
void FillCubicTangents(QuatTrack& track);

}  // namespace armature
