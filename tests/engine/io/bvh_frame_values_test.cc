// The frame lines' values as the reader stores them, against independent
// readings of the same text: every spelling of a number gives strtod's double
// (the reader's fast path for plain decimals must agree bit for bit with the
// general one), rotations are EulerToQuaternion of the values in degrees, and
// the line rules (blank lines, CR LF, tabs, a last line without a break,
// junk glued to a number) hold with the line numbers right.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "armature/engine/io/bvh/bvh.h"
#include "armature/engine/math/rotation.h"

namespace armature {
namespace {

constexpr double kDegree = std::numbers::pi / 180.0;

// A root with the given channels (OFFSET 0 0 0), `frames` declared.
std::string OneJointBvh(const std::string& channels, size_t frames, const std::string& frame_lines) {
  return "HIERARCHY\nROOT A\n{\n  OFFSET 0 0 0\n  CHANNELS " + channels +
         "\n  End Site\n  {\n    OFFSET 0 1 0\n  }\n}\nMOTION\nFrames: " + std::to_string(frames) +
         "\nFrame Time: 0.1\n" + frame_lines;  // frame lines start on line 14
}

// Decimal spellings a writer may produce: signs (also '+'), no integer or no
// fraction part, leading zeros, up to 30 digits (beyond what a double holds
// and beyond the 19 the fast path takes), exponents.
std::string RandomNumberSpelling(std::mt19937& rng) {
  auto pick = [&rng](int n) { return static_cast<int>(rng() % static_cast<unsigned>(n)); };
  std::string s;
  const int sign = pick(4);
  if (sign == 1) s += '-';
  if (sign == 2) s += '+';
  const int int_digits = pick(4) == 0 ? 0 : 1 + pick(pick(2) == 0 ? 4 : 18);
  const bool point = pick(5) != 0;
  const int fraction_digits = point ? (pick(3) == 0 ? 0 : pick(26)) : 0;
  auto digit = [&] { return static_cast<char>('0' + pick(10)); };
  for (int i = 0; i < int_digits; ++i) s += (i == 0 && pick(3) == 0) ? '0' : digit();
  if (point) s += '.';
  for (int i = 0; i < fraction_digits; ++i) s += digit();
  if (int_digits + fraction_digits == 0) s += '7';
  if (pick(8) == 0) s += std::string(pick(2) ? "e" : "E") + (pick(2) ? "-" : "") + std::to_string(pick(30));
  return s;
}

TEST(BvhFrameValues, EveryNumberSpellingReadsAsStrtodReadsIt) {
  std::mt19937 rng(15);
  std::vector<std::string> tokens = {"0",
                                     "-0",
                                     "+0",
                                     "1.",
                                     ".5",
                                     "-.5",
                                     "+.5",
                                     "00000123.4500",
                                     "9007199254740992",
                                     "9007199254740993",
                                     "9007199254740992.5",
                                     "0.1",
                                     "-0.30000000000000004",
                                     "3.14159265358979323846264338",
                                     "1234567890123456789",
                                     "12345678901234567890",
                                     "0.0000000000000000000001",
                                     "0.00000000000000000000001",
                                     "179.999999",
                                     "-179.999999",
                                     "1e2",
                                     "1.5E-3",
                                     "-36.000000"};
  while (tokens.size() < 30000) tokens.push_back(RandomNumberSpelling(rng));
  while (tokens.size() % 3 != 0) tokens.push_back("1");
  std::string lines;
  for (size_t i = 0; i < tokens.size(); i += 3) lines += tokens[i] + " " + tokens[i + 1] + "\t" + tokens[i + 2] + "\n";
  const size_t frames = tokens.size() / 3;
  const StatusOr<BvhData> d = ParseBvh(OneJointBvh("3 Xposition Yposition Zposition", frames, lines));
  ASSERT_TRUE(d.ok()) << d.status().message();
  const auto& values = d->clip->joints[0].translation.values;
  ASSERT_EQ(values.size(), frames);
  size_t mismatches = 0;
  for (size_t i = 0; i < tokens.size(); ++i) {
    const double expected = std::strtod(tokens[i].c_str(), nullptr);
    const double got = values[i / 3][static_cast<int>(i % 3)];
    if (got != expected && ++mismatches <= 10)
      ADD_FAILURE() << "'" << tokens[i] << "' read as " << got << ", strtod gives " << expected;
  }
  EXPECT_EQ(mismatches, 0u);
}

// The reader's inline sine and cosine (engine/src/io/bvh/euler_degrees.h) are
// within 1 ulp of libm's: the quaternions within 1e-15 of EulerToQuaternion's,
// also near quarter turns (where the range reduction switches quadrant) and
// for angles of many turns.
TEST(BvhFrameValues, RotationsAreEulerToQuaternionOfTheValuesInDegrees) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> uniform(-400.0, 400.0);
  std::uniform_int_distribution<int> quarter(-12, 12);
  std::uniform_real_distribution<double> tiny(-1e-6, 1e-6);
  auto angle = [&](int f) {
    switch (f % 4) {
      case 0: return uniform(rng);
      case 1: return 90.0 * quarter(rng) + tiny(rng);  // near a quadrant switch
      case 2: return uniform(rng) * 1000.0;            // many turns
      default: return uniform(rng) * 1e7;              // beyond the inline range: libm's
    }
  };
  double worst = 0;
  for (const std::string order : {"ZXY", "XYZ", "YZX", "ZY", "X"}) {
    std::vector<Axis> axes;
    std::string channels = std::to_string(order.size());
    for (char a : order) {
      axes.push_back(static_cast<Axis>(a - 'X'));
      channels += std::string(" ") + a + "rotation";
    }
    std::vector<std::vector<std::string>> rows;
    std::string lines;
    for (int f = 0; f < 2000; ++f) {
      std::vector<std::string> row;
      for (size_t k = 0; k < order.size(); ++k) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.9f", angle(f));
        row.push_back(buf);
        lines += (k ? " " : "") + row.back();
      }
      lines += "\n";
      rows.push_back(row);
    }
    const StatusOr<BvhData> d = ParseBvh(OneJointBvh(channels, rows.size(), lines));
    ASSERT_TRUE(d.ok()) << d.status().message();
    const auto& values = d->clip->joints[0].rotation.values;
    ASSERT_EQ(values.size(), rows.size());
    for (size_t f = 0; f < rows.size(); ++f) {
      std::vector<double> radians;
      for (const std::string& v : rows[f]) radians.push_back(std::strtod(v.c_str(), nullptr) * kDegree);
      const Eigen::Quaterniond expected = EulerToQuaternion(axes, radians);
      const double error = (values[f].coeffs() - expected.coeffs()).cwiseAbs().maxCoeff();
      worst = std::max(worst, error);
      ASSERT_LT(error, 1e-15) << order << " frame " << f << ": " << rows[f][0];
    }
  }
  std::printf("largest difference from EulerToQuaternion: %.3g\n", worst);
}

TEST(BvhFrameValues, BlankLinesCrLfTabsAndALastLineWithoutABreak) {
  const std::string lines = "\n \t\r\n1\t2  3\r\n\v\f\n\n  4 5 6  \r\n7 +8 -9";
  const StatusOr<BvhData> d = ParseBvh(OneJointBvh("3 Xposition Yposition Zposition", 3, lines));
  ASSERT_TRUE(d.ok()) << d.status().message();
  const auto& v = d->clip->joints[0].translation.values;
  ASSERT_EQ(v.size(), 3u);
  EXPECT_EQ(v[0], Eigen::Vector3d(1, 2, 3));
  EXPECT_EQ(v[1], Eigen::Vector3d(4, 5, 6));
  EXPECT_EQ(v[2], Eigen::Vector3d(7, 8, -9));
  EXPECT_TRUE(d->warnings.empty());
}

void ExpectFrameError(const std::string& lines, size_t frames, const std::string& message) {
  const StatusOr<BvhData> d = ParseBvh(OneJointBvh("3 Xposition Yposition Zposition", frames, lines));
  ASSERT_FALSE(d.ok()) << "expected: " << message;
  EXPECT_EQ(d.status().code(), StatusCode::kInvalidArgument);
  EXPECT_EQ(d.status().message(), message);
}

TEST(BvhFrameValues, MistakesNameTheFrameTheValueAndTheLine) {
  // Line 14 is the first frame line; blank lines count.
  ExpectFrameError("1 2 3\n\n\n4 5.5x 6\n", 2, "line 17: frame 1 value 2 '5.5x' is not a number");
  ExpectFrameError("1 2 3\n4 5 6-\n", 2, "line 15: frame 1 value 3 '6-' is not a number");
  ExpectFrameError("1 2 3\r\n4 5 1e400\r\n", 2, "line 15: frame 1 value 3 '1e400' is not a number");
  ExpectFrameError("1 2 3\n4 5 nan\n", 2, "line 15: frame 1 value 3 'nan' is not finite");
  ExpectFrameError("1 2 3 4 x\n", 1, "line 14: frame 0 value 5 'x' is not a number");
  ExpectFrameError("1 2 3 4\n", 1, "line 14: frame 0 has 4 values, expected 3");
  ExpectFrameError("\n1 2\n", 1, "line 15: frame 0 has 2 values, expected 3");
  ExpectFrameError("1 2 3\n\n  \n", 2, "line 17: file ends after 1 of the 2 frames that 'Frames:' on line 12 declares");
  ExpectFrameError("1 2 3", 2, "line 14: file ends after 1 of the 2 frames that 'Frames:' on line 12 declares");
  ExpectFrameError("", 1, "line 14: file ends after 0 of the 1 frames that 'Frames:' on line 12 declares");
}

TEST(BvhFrameValues, ExtraLinesAfterBlankOnesAreCountedFromTheirLine) {
  const StatusOr<BvhData> d = ParseBvh(OneJointBvh("3 Xposition Yposition Zposition", 1, "1 2 3\n\n4 5 6\n \n7 8 9"));
  ASSERT_TRUE(d.ok()) << d.status().message();
  ASSERT_EQ(d->warnings.size(), 1u);
  EXPECT_EQ(d->warnings[0], "line 16: 2 frame lines beyond Frames: 1 ignored");
}

}  // namespace
}  // namespace armature
