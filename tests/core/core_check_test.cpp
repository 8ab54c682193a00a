// HSR_CHECK: always on (this suite runs in Release too), prints the expression, both values
// and file:line, and aborts.

#include <gtest/gtest.h>

#include "core/check.hpp"

namespace hsr {
namespace {

TEST(CheckDeathTest, FailedCheckPrintsBothValuesAndAborts) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");  // oneTBB may have started threads
  const int tiles = 3, expected = 4;
  EXPECT_DEATH(
      HSR_CHECK_EQ(tiles, expected),
      "internal check failed at .*core_check_test.cpp:[0-9]+: tiles == expected \\(3 vs 4\\)");
  EXPECT_DEATH(HSR_CHECK(tiles > expected), "HSR_CHECK\\(tiles > expected\\)");
}

TEST(CheckDeathTest, PassingChecksDoNothing) {
  HSR_CHECK(1 + 1 == 2);
  HSR_CHECK_LE(2, 2);
  HSR_CHECK_NE(1, 2);
  SUCCEED();
}

}  // namespace
}  // namespace hsr
