// Invariant checks (util/check.h): a failed check is an InternalError that
// names the condition and prints both operands.
#include <gtest/gtest.h>

#include "fluidtex/util/check.h"

namespace fluidtex {
namespace {

TEST(Check, FailureNamesTheConditionAndBothOperands) {
  const int have = 7;
  const std::size_t want = 9;
  try {
    FLUIDTEX_CHECK_EQ(have, want);
    FAIL() << "check passed";
  } catch (const InternalError& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("test_check.cpp:"), std::string::npos) << m;
    EXPECT_NE(m.find("check failed: have == want (7 vs 9)"), std::string::npos) << m;
  }
  EXPECT_NO_THROW(FLUIDTEX_CHECK_LT(have, want));
  EXPECT_THROW(FLUIDTEX_CHECK(have > 8), InternalError);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(FLUIDTEX_CHECK_GT(nan, 0.0), InternalError);  // NaN fails every comparison
}

TEST(Check, OperandsAreEvaluatedOnce) {
  int calls = 0;
  auto next = [&] { return ++calls; };
  FLUIDTEX_CHECK_EQ(next(), 1);
  EXPECT_EQ(calls, 1);
}

TEST(Check, DebugChecksOnlyInDebugBuilds) {
  int evaluated = 0;
  auto bad = [&] {
    ++evaluated;
    return false;
  };
#ifdef NDEBUG
  EXPECT_NO_THROW(FLUIDTEX_DCHECK(bad()));
  EXPECT_EQ(evaluated, 0);
#else
  EXPECT_THROW(FLUIDTEX_DCHECK(bad()), InternalError);
  EXPECT_EQ(evaluated, 1);
#endif
}

}  // namespace
}  // namespace fluidtex
