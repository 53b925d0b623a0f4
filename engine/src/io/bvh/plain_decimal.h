// The BVH reader's fast path for frame values, which are almost all plain
// decimals ("-12.345678"): one IEEE division, exactly rounded (Clinger's fast
// path: a mantissa of at most 2^53 and a power of ten of at most 10^22 are
// both exact doubles), so the result is the one from_chars gives. (Reading
// eight digits at a time, SWAR, measured 10 % slower on the CMU file.)
#pragma once

#include <cstddef>
#include <cstdint>

namespace armature::io_detail {

// Reads "[+-]digits[.digits]" at `p` into `*out` and returns its end, or
// null when the text is anything else (no digit, more than 19 digits, a
// mantissa beyond 2^53, ...) and the caller must take the general path. What
// follows the number is the caller's to check.
inline const char* ParsePlainDecimal(const char* p, const char* end, double* out) {
  static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                      1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  bool negative = false;
  if (p < end && (*p == '-' || *p == '+')) negative = *p++ == '-';
  uint64_t mantissa = 0;
  const char* digits_start = p;
  while (p < end && static_cast<unsigned>(*p - '0') < 10) mantissa = mantissa * 10 + static_cast<unsigned>(*p++ - '0');
  size_t digits = static_cast<size_t>(p - digits_start), fraction = 0;
  if (p < end && *p == '.') {
    const char* fraction_start = ++p;
    while (p < end && static_cast<unsigned>(*p - '0') < 10)
      mantissa = mantissa * 10 + static_cast<unsigned>(*p++ - '0');
    fraction = static_cast<size_t>(p - fraction_start);
    digits += fraction;
  }
  // 19 digits cannot overflow 64 bits; the mantissa must be exact as a double.
  if (digits == 0 || digits > 19 || fraction > 22 || mantissa > (uint64_t{1} << 53)) return nullptr;
  // A multiplication by ±1 (exact), not a branch on a sign that is random.
  static constexpr double kSign[2] = {1.0, -1.0};
  *out = static_cast<double>(mantissa) / kPow10[fraction] * kSign[negative];
  return p;
}

}  // namespace armature::io_detail
