// gtest main for MPI tests: Tpetra::ScopeGuard, output of rank 0 only; a run that skipped a
// case exits with the skip code (on every rank: the skips do not depend on the rank).
#include <gtest/gtest.h>

#include <Tpetra_Core.hpp>

#include "skip_code.hpp"

int main(int argc, char** argv) {
  Tpetra::ScopeGuard guard(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  if (Tpetra::getDefaultComm()->getRank() != 0) {
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  return traverse::testing::exit_code_with_skips(RUN_ALL_TESTS());
}
