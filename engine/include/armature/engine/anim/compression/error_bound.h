// A compressed clip's error bound: how far, in the skeleton's units, a
// virtual point at `shell_distance` from any joint along its local axes may
// move in world space against the clip as stored (ACL's metric,
// docs/error_metrics.md in ACL 2.1).
#pragma once

#include <string>
#include <string_view>

#include "armature/base/status.h"
#include "armature/engine/anim/skeleton.h"

namespace armature {

// What an import asks for: a bound in centimetres, or `exact` (the stored
// key values kept bit for bit).
struct ClipPrecision {
  static constexpr double kDefaultCentimetres = 0.01;  // ACL's default
  static constexpr double kShellCentimetres = 3.0;     // ACL's default shell distance
  static constexpr double kMaxCentimetres = 10.0;

  bool exact = false;
  double centimetres = kDefaultCentimetres;
};

// The bound in the skeleton's units.
struct ErrorBound {
  double precision = 0;       // largest displacement allowed
  double shell_distance = 0;  // virtual points' distance from their joint
};

// Skeleton units per centimetre: Skeleton::units_per_centimetre when set
// (a glTF file Armature wrote says so), else the rule: a skeleton without BVH channels
// (glTF) is in metres (0.01), as glTF 2.0 says. A BVH skeleton, which has no
// unit, is in centimetres (1) when its rest pose (joints and end sites, in
// world space) spans 10 units or more along some axis, else in metres: a
// human is 1.7 units tall in metres and 170 in centimetres; CMU's BVH units
// (about 35 for a body) count as centimetres, as ACL sees them unscaled.
double UnitsPerCentimetre(const Skeleton& skeleton);

// INVALID_ARGUMENT naming `precision` unless the bound is exact or in
// (0, 10] centimetres (NaN refused).
Status CheckClipPrecision(const ClipPrecision& precision);

// The one reading of a precision as text (ImportAsset's `precision`, the CLI's
// and the server's --clip-error): "exact", or a bound in centimetres ("0.01").
// Empty gives `fallback`. INVALID_ARGUMENT naming `field` for anything else or
// a bound CheckClipPrecision refuses (0, negative, NaN, over 10 cm).
StatusOr<ClipPrecision> ParseClipPrecision(std::string_view text, std::string_view field,
                                           const ClipPrecision& fallback = {});

// "exact", or the centimetres as the shortest text that reads back the same.
std::string ClipPrecisionText(const ClipPrecision& precision);

// The bound in the skeleton's units: 0.01 cm at 3 cm is 0.01 at 3 for a
// skeleton in centimetres, 0.0001 at 0.03 for one in metres. Checks first.
StatusOr<ErrorBound> ResolveErrorBound(const Skeleton& skeleton, const ClipPrecision& precision);

}  // namespace armature
