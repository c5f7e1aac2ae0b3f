#include "varsfm/util/option_check.h"

#include <limits>
#include <string>

#include <gtest/gtest.h>

namespace varsfm {
namespace {

// The one-line message of the OptionError `check` throws, or "" when it accepts.
template <typename Check>
std::string MessageOf(Check check) {
  try {
    check();
  } catch (const OptionError& e) {
    return e.what();
  }
  return "";
}

constexpr double kNan = std::numeric_limits<double>::quiet_NaN();
constexpr double kInf = std::numeric_limits<double>::infinity();

TEST(OptionCheck, NamesTheOptionTheRangeAndTheValue) {
  EXPECT_EQ(MessageOf([] { CheckAtLeast("--threads", -3, 0); }),
            "--threads: expected an integer >= 0, got -3");
  EXPECT_EQ(MessageOf([] { CheckGreaterThan("--max-error", 0.0, 0); }),
            "--max-error: expected a number > 0, got 0");
  EXPECT_EQ(MessageOf([] { CheckInRange("--min-zncc", 1.5, -1, 1); }),
            "--min-zncc: expected a number in [-1, 1], got 1.5");
  EXPECT_EQ(MessageOf([] { CheckInHalfOpenRange("--ratio", 0.0, 0, 1); }),
            "--ratio: expected a number in (0, 1], got 0");
}

TEST(OptionCheck, AcceptsTheBounds) {
  EXPECT_EQ(MessageOf([] { CheckAtLeast("a", 0, 0); }), "");
  EXPECT_EQ(MessageOf([] { CheckInRange("b", -1.0, -1, 1); }), "");
  EXPECT_EQ(MessageOf([] { CheckInRange("c", 1.0, -1, 1); }), "");
  EXPECT_EQ(MessageOf([] { CheckInHalfOpenRange("d", 1.0, 0, 1); }), "");
  EXPECT_EQ(MessageOf([] { CheckFinite("e", -1e300); }), "");
}

TEST(OptionCheck, RejectsNanAndInfinityWhateverTheBounds) {
  for (const double bad : {kNan, kInf, -kInf}) {
    EXPECT_NE(MessageOf([&] { CheckAtLeast("a", bad, 0); }), "") << bad;
    EXPECT_NE(MessageOf([&] { CheckGreaterThan("b", bad, 0); }), "") << bad;
    EXPECT_NE(MessageOf([&] { CheckInRange("c", bad, -1e308, 1e308); }), "") << bad;
    EXPECT_NE(MessageOf([&] { CheckInHalfOpenRange("d", bad, 0, 1); }), "") << bad;
    EXPECT_NE(MessageOf([&] { CheckFinite("e", bad); }), "") << bad;
  }
  EXPECT_EQ(MessageOf([] { CheckGreaterThan("--ratio", kNan, 0); }),
            "--ratio: expected a number > 0, got nan");
}

TEST(OptionCheck, NamedRangesAreTheirGeneralChecks) {
  EXPECT_EQ(MessageOf([] { CheckPositive("--sigma", 0.0); }),
            "--sigma: expected a number > 0, got 0");
  EXPECT_EQ(MessageOf([] { CheckPositive("--sigma", 1e-300); }), "");
  EXPECT_EQ(MessageOf([] { CheckNonNegative("--smoothing", -1); }),
            "--smoothing: expected an integer >= 0, got -1");
  EXPECT_EQ(MessageOf([] { CheckNonNegative("--smoothing", 0); }), "");
  EXPECT_EQ(MessageOf([] { CheckFraction("--min-component", 1.5); }),
            "--min-component: expected a number in [0, 1], got 1.5");
  EXPECT_EQ(MessageOf([] { CheckFraction("--min-component", 0.0); }), "");
  EXPECT_EQ(MessageOf([] { CheckFraction("--min-component", 1.0); }), "");
  EXPECT_NE(MessageOf([] { CheckFraction("--min-component", kNan); }), "");
}

TEST(OptionCheck, OptionErrorIsAVarsfmError) { EXPECT_THROW(CheckAtLeast("x", -1, 0), Error); }

}  // namespace
}  // namespace varsfm
