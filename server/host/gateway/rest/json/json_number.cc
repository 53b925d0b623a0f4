#include "server/host/gateway/rest/json/json_number.h"

#include <algorithm>
#include <charconv>
#include <cstdint>
#include <cmath>
#include <limits>
#include <type_traits>

#include <google/protobuf/stubs/strutil.h>

namespace armature::server::gateway {
namespace {

// A decimal's significant digits (no trailing zeros) and its exponent, from
// to_chars' scientific form ("-1.2345e-05").
struct Decimal {
  bool negative = false;
  char digits[24];
  int count = 0;
  int exponent = 0;
};

Decimal ParseScientific(const char* p, const char* end) {
  Decimal d;
  if (*p == '-') d.negative = true, ++p;
  for (; p < end && *p != 'e'; ++p)
    if (*p != '.') d.digits[d.count++] = *p;
  while (d.count > 1 && d.digits[d.count - 1] == '0') --d.count;
  int exponent = 0;
  bool negative_exponent = false;
  for (++p; p < end; ++p) {
    if (*p == '-')
      negative_exponent = true;
    else if (*p != '+')
      exponent = exponent * 10 + (*p - '0');
  }
  d.exponent = negative_exponent ? -exponent : exponent;
  return d;
}

// printf's %.<precision>g of a decimal with at most `precision` digits.
void AppendGeneral(const Decimal& d, int precision, std::string* out) {
  if (d.negative) out->push_back('-');
  const int x = d.exponent;
  if (x < -4 || x >= precision) {
    out->push_back(d.digits[0]);
    if (d.count > 1) {
      out->push_back('.');
      out->append(d.digits + 1, d.count - 1);
    }
    out->push_back('e');
    out->push_back(x < 0 ? '-' : '+');
    const int magnitude = x < 0 ? -x : x;
    if (magnitude < 10) out->push_back('0');
    char buf[8];
    out->append(buf, std::to_chars(buf, buf + sizeof buf, magnitude).ptr);
    return;
  }
  if (x < 0) {
    out->append("0.");
    out->append(static_cast<size_t>(-x - 1), '0');
    out->append(d.digits, d.count);
    return;
  }
  const int integer_digits = x + 1;
  if (d.count <= integer_digits) {
    out->append(d.digits, d.count);
    out->append(static_cast<size_t>(integer_digits - d.count), '0');
    return;
  }
  out->append(d.digits, integer_digits);
  out->push_back('.');
  out->append(d.digits + integer_digits, d.count - integer_digits);
}

// A float's %.9g digits by double arithmetic: the float times a power of ten
// is within 1e-7 of exact, so it rounds right unless it lies near a half.
// False when it might not (then to_chars decides).
bool NineDigits(float value, Decimal* d) {
  static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,  1e8,  1e9,  1e10, 1e11,
                                      1e12, 1e13, 1e14, 1e15, 1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
  const int k = 8 - d->exponent;
  if (k > 22 || k < -22) return false;
  const double magnitude = std::fabs(static_cast<double>(value));
  const double scaled = k >= 0 ? magnitude * kPow10[k] : magnitude / kPow10[-k];
  const double whole = std::floor(scaled);
  const double fraction = scaled - whole;
  if (std::fabs(fraction - 0.5) < 1e-6) return false;
  uint64_t n = static_cast<uint64_t>(whole) + (fraction > 0.5);
  if (n >= 1000000000) n /= 10, ++d->exponent;  // rounded up to the next power of ten
  char buf[16];
  char* end = std::to_chars(buf, buf + sizeof buf, n).ptr;
  d->count = static_cast<int>(end - buf);
  std::copy(buf, end, d->digits);
  while (d->count > 1 && d->digits[d->count - 1] == '0') --d->count;
  return true;
}

template <class T>
void AppendFinite(T value, int short_precision, int long_precision, std::string* out) {
  char buf[64];
  const auto shortest = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::scientific);
  Decimal d = ParseScientific(buf, shortest.ptr);
  // With all the digits the shortest text is also the closest one, i.e. printf's.
  if (d.count <= short_precision) return AppendGeneral(d, short_precision, out);
  if (d.count == long_precision) return AppendGeneral(d, long_precision, out);
  if constexpr (std::is_same_v<T, float>) {
    if (NineDigits(value, &d)) return AppendGeneral(d, long_precision, out);
  }
  const auto precise = std::to_chars(buf, buf + sizeof buf, value, std::chars_format::general, long_precision);
  out->append(buf, precise.ptr);
}

// printf's digits: 6 then 9 for a float, 15 then 17 for a double.
template <class T>
void AppendNumber(T value, std::string* out) {
  if (std::isnan(value)) return out->append("\"NaN\""), void();
  if (std::isinf(value)) return out->append(value > 0 ? "\"Infinity\"" : "\"-Infinity\""), void();
  constexpr bool kFloat = std::is_same_v<T, float>;
  // Below twice the smallest normal, protobuf's read-back may fail on strtof's range error.
  if (value != 0 && std::fabs(value) < 2 * std::numeric_limits<T>::min())
    return out->append(kFloat ? google::protobuf::SimpleFtoa(value) : google::protobuf::SimpleDtoa(value)), void();
  AppendFinite(value, kFloat ? 6 : 15, kFloat ? 9 : 17, out);
}

}  // namespace

void AppendJsonFloat(float value, std::string* out) { AppendNumber(value, out); }
void AppendJsonDouble(double value, std::string* out) { AppendNumber(value, out); }

}  // namespace armature::server::gateway
