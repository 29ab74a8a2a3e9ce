// gtest main for tests without MPI: a run that skipped a case exits with the skip code.
#include <gtest/gtest.h>

#include "skip_code.hpp"

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  return traverse::testing::exit_code_with_skips(RUN_ALL_TESTS());
}
