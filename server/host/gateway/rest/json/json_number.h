// Floats and doubles as protobuf's JSON printer writes them (3.21's
// SimpleFtoa/SimpleDtoa): printf's "%.6g" ("%.15g" for doubles) when that
// reads back as the same value, else "%.9g" ("%.17g"); NaN and infinities as
// the quoted strings "NaN", "Infinity", "-Infinity".
//
// printf is slow (about 0.5 µs a float with its read-back check); this gets
// the same text from std::to_chars: the shortest text that reads back has at
// most 6 (15) digits exactly when "%.6g" reads back, and then both are the
// same number, written in %g style; otherwise to_chars with a precision is
// printf's %.9g (%.17g). Subnormals, where strtof's range error also counts,
// go to protobuf's own functions.
#pragma once

#include <string>

namespace armature::server::gateway {

void AppendJsonFloat(float value, std::string* out);
void AppendJsonDouble(double value, std::string* out);

}  // namespace armature::server::gateway
