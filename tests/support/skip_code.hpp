#pragma once
// The exit code of a test executable whose run skipped a case (GTEST_SKIP) and failed none:
// ctest shows it as skipped (SKIP_RETURN_CODE, cmake/TraverseTesting.cmake), not as passed.
#include <gtest/gtest.h>

namespace traverse::testing {

constexpr int kSkippedExitCode = 77;

/// RUN_ALL_TESTS()'s result, or kSkippedExitCode when it passed with a case skipped.
inline int exit_code_with_skips(int gtest_result) {
  if (gtest_result == 0 && ::testing::UnitTest::GetInstance()->skipped_test_count() > 0) return kSkippedExitCode;
  return gtest_result;
}

}  // namespace traverse::testing
