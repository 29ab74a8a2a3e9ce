// Start-up: --help, --version and check never start MPI outside a launcher, so they work
// where MPI cannot start at all (a run there fails with MPI's own message and a non-zero exit
// code); under mpiexec every rank takes part and one rank reports.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "process.hpp"

namespace fs = std::filesystem;

namespace {

const std::string kExe = TRAVERSE_EXE;
const fs::path kScene = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "default.yaml";
// An Open MPI setting that makes MPI_Init fail: a point-to-point layer that does not exist.
const std::string kBrokenMpi = "OMPI_MCA_pml=no_such_pml ";

std::size_t count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto p = text.find(what); p != std::string::npos; p = text.find(what, p + 1)) ++n;
  return n;
}

}  // namespace

TEST(Startup, HelpVersionAndCheckWorkWhereMpiCannotStart) {
  const fs::path out = fs::path(TRAVERSE_BINARY_DIR) / "test-scratch" / "startup" / "run.h5";
  fs::remove_all(out.parent_path());
  fs::create_directories(out.parent_path());
  // The control: in this environment a run, which starts MPI, cannot start, and writes nothing.
  const auto run = traverse::testing::run_command(kBrokenMpi + kExe + " run " + kScene.string() + " -o " +
                                                  out.string() + " --set mesh.ds=0.1 -q");
  ASSERT_NE(run.code, 0) << "this MPI ignores OMPI_MCA_pml=no_such_pml; the control does not hold:\n" << run.out;
  EXPECT_FALSE(fs::exists(out));

  const auto version = traverse::testing::run_command(kBrokenMpi + kExe + " --version");
  EXPECT_EQ(version.code, 0) << version.out;
  EXPECT_EQ(version.out.rfind("traverse ", 0), 0u) << version.out;
  const auto help = traverse::testing::run_command(kBrokenMpi + kExe + " --help");
  EXPECT_EQ(help.code, 0) << help.out;
  const auto check = traverse::testing::run_command(kBrokenMpi + kExe + " check " + kScene.string());
  EXPECT_EQ(check.code, 0) << check.out;
  EXPECT_NE(check.out.find(": valid ("), std::string::npos) << check.out;
  EXPECT_NE(check.out.find("per rank"), std::string::npos) << check.out;
  // Bad input is still found and reported without MPI.
  const auto bad = traverse::testing::run_command(kBrokenMpi + kExe + " check " + kScene.string() + " --set mesh.ds=-1");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_NE(bad.out.find("mesh.ds"), std::string::npos) << bad.out;
}

TEST(Startup, UnderMpiexecOneRankReports) {
  const std::string mpiexec = std::string(TRAVERSE_MPIEXEC) + " --allow-run-as-root --oversubscribe -n 2 ";
  const auto version = traverse::testing::run_command(mpiexec + kExe + " --version");
  EXPECT_EQ(version.code, 0) << version.out;
  EXPECT_EQ(count(version.out, "traverse "), 1u) << version.out;
  // check under the launcher starts MPI: the memory limit is shared by the 2 ranks.
  const auto check = traverse::testing::run_command(mpiexec + kExe + " check " + kScene.string());
  EXPECT_EQ(check.code, 0) << check.out;
  EXPECT_EQ(count(check.out, ": valid ("), 1u) << check.out;
  EXPECT_NE(check.out.find("2 ranks"), std::string::npos) << check.out;
  const auto bad = traverse::testing::run_command(mpiexec + kExe + " check " + kScene.string() + " --set mesh.ds=-1");
  EXPECT_EQ(bad.code, 2) << bad.out;
  EXPECT_EQ(count(bad.out, "traverse: bad scene:"), 1u) << bad.out;
}
