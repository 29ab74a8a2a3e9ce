// Start-up pays only for what a command uses (docs/developer.md, "Start-up"): --help,
// --version and check (outside an MPI launcher) never start MPI, so they work where MPI
// cannot start at all; under mpiexec every rank takes part and one rank reports.
#include <gtest/gtest.h>

#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
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

TEST(Startup, CommandsWithoutSolverWorkWhereMpiCannotStart) {
  const fs::path out = fs::path(TRAVERSE_BINARY_DIR) / "test-scratch" / "startup" / "run.h5";
  fs::remove_all(out.parent_path());
  fs::create_directories(out.parent_path());
  // The control: in this environment a run, which needs MPI, cannot start.
  // (Its session directory, left behind by the failed MPI_Init, goes to the scratch folder.)
  const auto run = traverse::testing::run_command("TMPDIR=" + out.parent_path().string() + " " + kBrokenMpi + kExe +
                                                  " run " + kScene.string() + " -o " + out.string() + " --set mesh.ds=0.1 -q");
  std::printf("run with a broken MPI setting: exit %d\n", run.code);
  if (run.code == 0) GTEST_SKIP() << "this MPI ignores OMPI_MCA_pml; the environment does not break MPI_Init";

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

TEST(Startup, SingleProcessRunRemovesItsSessionAndStaleOnes) {
  // A run outside a launcher makes its own Open MPI session directory under TMPDIR and
  // removes it at the end; it also removes the ones of processes that no longer exist
  // (killed runs), and leaves a live process's alone.
  const fs::path tmp = fs::path(TRAVERSE_BINARY_DIR) / "test-scratch" / "startup-tmp";
  fs::remove_all(tmp);
  fs::create_directories(tmp);
  const pid_t dead = fork();
  if (dead == 0) _exit(0);
  ASSERT_GT(dead, 0);
  waitpid(dead, nullptr, 0);
  const fs::path stale = tmp / "traverse-mpi-stale0", live = tmp / "traverse-mpi-live00";
  for (const auto& [dir, pid] : {std::pair{stale, long(dead)}, std::pair{live, long(getpid())}}) {
    fs::create_directories(dir / "ompi.host.0");
    std::ofstream(dir / "owner") << pid << "\n";
  }
  const fs::path out = tmp / "run.h5";
  const auto run = traverse::testing::run_command("TMPDIR=" + tmp.string() + " " + kExe + " run " + kScene.string() +
                                                  " -o " + out.string() + " --set mesh.ds=0.1 -q");
  ASSERT_EQ(run.code, 0) << run.out;
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(tmp))
    if (e.path().filename().string().rfind("traverse-mpi-", 0) == 0) left.push_back(e.path().filename().string());
  std::printf("session directories left: %zu\n", left.size());
  EXPECT_FALSE(fs::exists(stale)) << "the directory of a process that is gone stays";
  EXPECT_TRUE(fs::exists(live)) << "the directory of a live process was removed";
  EXPECT_EQ(left, std::vector<std::string>{"traverse-mpi-live00"}) << "the run left its own session directory";
}
