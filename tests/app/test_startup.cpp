// Start-up pays only for what a command uses (docs/developer.md, "Start-up"): --help,
// --version, check, a run and a sweep in one process on block storage (outside an MPI launcher) never
// start MPI, so they work where MPI cannot start at all; under mpiexec every rank takes part
// and one rank reports.
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "mpi_session.hpp"
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
  // The control: in this environment a run that needs MPI (a continuation, handed over to
  // traverse-trilinos, which starts MPI) cannot start. (Its session directory, left behind by
  // the failed MPI_Init, goes to the scratch folder.)
  const fs::path statics = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "statics" / "euler_buckling.yaml";
  const auto needs = traverse::testing::run_command("TMPDIR=" + out.parent_path().string() + " " + kBrokenMpi + kExe +
                                                    " run " + statics.string() + " -o " + out.string() + " -q");
  std::printf("continuation run with a broken MPI setting: exit %d\n", needs.code);
  if (needs.code == 0) GTEST_SKIP() << "this MPI ignores OMPI_MCA_pml; the environment does not break MPI_Init";
  fs::remove(out);
  fs::remove(fs::path(out).replace_extension(".xmf"));

  // A rod run in one process on block storage needs no MPI: it runs, and writes its file.
  const auto run = traverse::testing::run_command(kBrokenMpi + kExe + " run " + kScene.string() + " -o " + out.string() +
                                                  " --set mesh.ds=0.1 -q");
  EXPECT_EQ(run.code, 0) << run.out;
  EXPECT_TRUE(fs::exists(out));
  // So does a sweep in one process: every case runs, the index is written.
  const fs::path sweep_dir = out.parent_path() / "sweep";
  const auto sweep = traverse::testing::run_command(kBrokenMpi + kExe + " sweep " + kScene.string() +
                                                    " --set mesh.ds=0.1 --vary loads.F.speed=2,3 -q -o " +
                                                    sweep_dir.string());
  EXPECT_EQ(sweep.code, 0) << sweep.out;
  EXPECT_TRUE(fs::exists(sweep_dir / "case_0000.h5"));
  EXPECT_TRUE(fs::exists(sweep_dir / "case_0001.h5"));
  std::ifstream index(sweep_dir / "index.csv");
  std::string line;
  int complete = 0;
  while (std::getline(index, line)) complete += line.find(",complete,0,") != std::string::npos ? 1 : 0;
  EXPECT_EQ(complete, 2) << "index.csv of the sweep without MPI";

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
  // A run that starts MPI outside a launcher (traverse-trilinos's; traverse's own runs do not
  // start MPI) makes its own Open MPI session directory under TMPDIR and removes it at the
  // end; it also removes the ones of processes that no longer exist (killed runs), and leaves
  // a live process's alone.
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
  const std::string trilinos = (fs::path(kExe).parent_path() / "traverse-trilinos").string();
  const auto run = traverse::testing::run_command("TMPDIR=" + tmp.string() + " " + trilinos + " run " +
                                                  kScene.string() + " -o " + out.string() + " --set mesh.ds=0.1 -q");
  ASSERT_EQ(run.code, 0) << run.out;
  std::vector<std::string> left;
  for (const auto& e : fs::directory_iterator(tmp))
    if (e.path().filename().string().rfind("traverse-mpi-", 0) == 0) left.push_back(e.path().filename().string());
  std::printf("session directories left: %zu\n", left.size());
  EXPECT_FALSE(fs::exists(stale)) << "the directory of a process that is gone stays";
  EXPECT_TRUE(fs::exists(live)) << "the directory of a live process was removed";
  EXPECT_EQ(left, std::vector<std::string>{"traverse-mpi-live00"}) << "the run left its own session directory";
}

// MPI started by traverse (here a one-process traverse-trilinos run, whose singleton start
// runs hwloc) loads none of hwloc's device or libxml2 plugins (HWLOC_PLUGINS_BLACKLIST, set
// unless the environment sets it: docs/developer.md, "Start-up"). The control: with the
// variable set empty, the plugins this hwloc has are loaded (none: nothing to show here).
TEST(Startup, MpiStartLoadsNoHwlocDevicePlugins) {
  const fs::path dir = fs::path(TRAVERSE_BINARY_DIR) / "test-scratch" / "startup-hwloc";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string trilinos = (fs::path(kExe).parent_path() / "traverse-trilinos").string();
  auto plugins = [&](const std::string& env, const std::string& name) {
    const auto r = traverse::testing::run_command(env + " LD_DEBUG=libs " + trilinos + " run " + kScene.string() +
                                                  " -o " + (dir / name).string() + " --set mesh.ds=0.1 -q");
    EXPECT_EQ(r.code, 0) << r.out.substr(0, 4000);
    // glibc's loader log names each image it maps ("calling init: /path/to/hwloc/hwloc_gl.so")
    std::size_t n = 0;
    for (const char* p : {"/hwloc_pci.so", "/hwloc_opencl.so", "/hwloc_gl.so", "/hwloc_xml_libxml.so"})
      n += count(r.out, p) > 0;
    return n;
  };
  const std::size_t control = plugins("HWLOC_PLUGINS_BLACKLIST=", "control.h5");
  std::printf("hwloc plugins loaded with HWLOC_PLUGINS_BLACKLIST set empty: %zu\n", control);
  if (control == 0) GTEST_SKIP() << "this hwloc loads none of these plugins: nothing to leave out";
  EXPECT_EQ(plugins("", "run.h5"), 0u) << "traverse's MPI start still loads hwloc device plugins";
}

// A sweep's ranks under Open MPI's launcher on one host open only the Open MPI components a
// sweep uses (app::sweep_components: docs/developer.md, "Start-up"): shared memory, not the
// collectives over many ranks nor the one-sided transport over a network; a selection the
// environment makes wins. The dynamic loader's log (LD_DEBUG=libs, in the ranks only) names
// each component the ranks load.
TEST(Startup, SweepRanksOpenOnlyTheComponentsASweepUses) {
  const fs::path dir = fs::path(TRAVERSE_BINARY_DIR) / "test-scratch" / "startup-sweep-components";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string mpiexec = std::string(TRAVERSE_MPIEXEC) + " --allow-run-as-root --oversubscribe -n 2 -x LD_DEBUG=libs ";
  auto loaded = [&](const std::string& env, const std::string& name) {
    const auto r = traverse::testing::run_command(mpiexec + env + kExe + " sweep " + kScene.string() + " -o " +
                                                  (dir / name).string() +
                                                  " --set mesh.ds=0.1 --set output.fields=[] --vary loads.F.speed=10,20 -q");
    EXPECT_EQ(r.code, 0) << r.out.substr(0, 4000);
    std::vector<std::string> names;
    for (const char* c : {"mca_btl_vader.so", "mca_osc_sm.so", "mca_coll_tuned.so", "mca_coll_han.so", "mca_osc_rdma.so"})
      if (count(r.out, std::string("/") + c) > 0) names.push_back(c);
    std::string list;
    for (const auto& n : names) list += n + " ";
    std::printf("%s: %s\n", name.c_str(), list.c_str());
    return list;
  };
  const std::string sweep = loaded("", "sweep");
  EXPECT_NE(sweep.find("mca_btl_vader.so"), std::string::npos) << sweep;
  EXPECT_NE(sweep.find("mca_osc_sm.so"), std::string::npos) << sweep;
  for (const char* c : {"mca_coll_tuned.so", "mca_coll_han.so", "mca_osc_rdma.so"})
    EXPECT_EQ(sweep.find(c), std::string::npos) << c << " loaded: " << sweep;
  // The environment's selection wins.
  const std::string chosen = loaded("-x OMPI_MCA_coll=basic,self,libnbc,tuned ", "chosen");
  EXPECT_NE(chosen.find("mca_coll_tuned.so"), std::string::npos) << chosen;
}

// traverse links no Trilinos library (not even Teuchos or Kokkos: its parameter lists are
// traverse's own) and hands the runs that need one over to the traverse-trilinos beside it
// (docs/developer.md, "Start-up"). The dynamic loader's own log (glibc's LD_DEBUG=libs) says
// which libraries each process image loaded.
TEST(Startup, OnlyRunsThatNeedTrilinosLoadIt) {
  const fs::path dir = fs::path(TRAVERSE_BINARY_DIR) / "test-scratch" / "startup-trilinos";
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string tpetra = "libtrilinos_tpetra.so", any_trilinos = "libtrilinos_";
  // The default scene, in one process: block storage, no Tpetra, no hand-over.
  const auto lean = traverse::testing::run_command("LD_DEBUG=libs " + kExe + " run " + kScene.string() + " -o " +
                                                   (dir / "lean.h5").string() + " --set mesh.ds=0.1 -q");
  EXPECT_EQ(lean.code, 0) << lean.out.substr(0, 4000);
  EXPECT_EQ(count(lean.out, any_trilinos), 0u) << "the default scene loaded a Trilinos library";
  // Nor the shared C++ runtime: traverse has it linked in (src/app/CMakeLists.txt), but for a
  // sanitizer build.
  if (!TRAVERSE_SANITIZED) {
    EXPECT_EQ(count(lean.out, "libstdc++.so"), 0u) << "traverse loaded libstdc++";
  }
  EXPECT_EQ(count(lean.out, "traverse-trilinos"), 0u);
  EXPECT_TRUE(fs::exists(dir / "lean.h5"));
  // A continuation run needs LOCA: handed over (the new image loads Tpetra), and it completes.
  const fs::path statics = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "statics" / "euler_buckling.yaml";
  const auto full = traverse::testing::run_command("LD_DEBUG=libs " + kExe + " run " + statics.string() + " -o " +
                                                   (dir / "full.h5").string() + " -q");
  EXPECT_EQ(full.code, 0) << full.out.substr(full.out.size() > 4000 ? full.out.size() - 4000 : 0);
  EXPECT_GE(count(full.out, tpetra), 1u) << "the continuation run did not load Tpetra";
  EXPECT_GE(count(full.out, "traverse-trilinos"), 1u);
  EXPECT_TRUE(fs::exists(dir / "full.h5"));
  // A sweep whose cases all step on block storage runs in traverse; one with a case on
  // another linear solver is handed over.
  const std::string sweep = " sweep " + kScene.string() + " --set mesh.ds=0.1 --set output.fields=[] -q --vary ";
  const auto lean_sweep = traverse::testing::run_command("LD_DEBUG=libs " + kExe + sweep + "loads.F.speed=2,3 -o " +
                                                         (dir / "sweep-lean").string());
  EXPECT_EQ(lean_sweep.code, 0) << lean_sweep.out.substr(0, 4000);
  EXPECT_EQ(count(lean_sweep.out, any_trilinos), 0u) << "a sweep on block storage loaded a Trilinos library";
  const auto full_sweep = traverse::testing::run_command("LD_DEBUG=libs " + kExe + sweep +
                                                         "'solver.Linear Solver=auto,KLU2' -o " +
                                                         (dir / "sweep-full").string());
  EXPECT_EQ(full_sweep.code, 0) << full_sweep.out.substr(full_sweep.out.size() > 4000 ? full_sweep.out.size() - 4000 : 0);
  EXPECT_GE(count(full_sweep.out, tpetra), 1u) << "a sweep with a KLU2 case did not load Tpetra";
  EXPECT_TRUE(fs::exists(dir / "sweep-full" / "index.csv"));
  // traverse alone (no traverse-trilinos beside it): what needs no Trilinos runs; what does is
  // refused with a message naming the missing executable (exit 1, no output file).
  const fs::path alone = dir / "alone";
  fs::create_directories(alone);
  fs::copy_file(kExe, alone / "traverse");
  const std::string exe = (alone / "traverse").string();
  const auto ok = traverse::testing::run_command(exe + " run " + kScene.string() + " -o " + (dir / "alone.h5").string() +
                                                 " --set mesh.ds=0.1 -q");
  EXPECT_EQ(ok.code, 0) << ok.out;
  const auto refused = traverse::testing::run_command(exe + " run " + statics.string() + " -o " +
                                                      (dir / "refused.h5").string() + " -q");
  std::printf("statics without traverse-trilinos: exit %d: %s", refused.code, refused.out.c_str());
  EXPECT_EQ(refused.code, 1) << refused.out;
  EXPECT_NE(refused.out.find((alone / "traverse-trilinos").string()), std::string::npos) << refused.out;
  EXPECT_FALSE(fs::exists(dir / "refused.h5"));
}

// Under a launcher, after MPI_Init: the process's loopback TCP connections (to the launcher's
// PMIx server) send at once (TCP_NODELAY); other sockets are left alone.
TEST(Startup, LoopbackConnectionsSendAtOnce) {
  auto nodelay = [](int fd) {
    int on = -1;
    socklen_t len = sizeof on;
    EXPECT_EQ(getsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &on, &len), 0);
    return on;
  };
  const int listener = socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_GE(listener, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  ASSERT_EQ(bind(listener, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  ASSERT_EQ(listen(listener, 1), 0);
  socklen_t len = sizeof a;
  ASSERT_EQ(getsockname(listener, reinterpret_cast<sockaddr*>(&a), &len), 0);
  const int client = socket(AF_INET, SOCK_STREAM, 0);
  ASSERT_EQ(connect(client, reinterpret_cast<sockaddr*>(&a), sizeof a), 0);
  const int server = accept(listener, nullptr, nullptr);
  ASSERT_GE(server, 0);
  const int unconnected = socket(AF_INET, SOCK_STREAM, 0);
  int pair[2];
  ASSERT_EQ(socketpair(AF_UNIX, SOCK_STREAM, 0, pair), 0);
  for (int fd : {client, server, listener, unconnected}) EXPECT_EQ(nodelay(fd), 0) << "Nagle on at first";

  EXPECT_EQ(traverse::app::send_control_messages_at_once(), 2);  // both ends of the connection
  EXPECT_NE(nodelay(client), 0);
  EXPECT_NE(nodelay(server), 0);
  EXPECT_EQ(nodelay(listener), 0);
  EXPECT_EQ(nodelay(unconnected), 0);
  // Data still flows both ways.
  ASSERT_EQ(write(client, "ab", 2), 2);
  char got[2] = {};
  ASSERT_EQ(read(server, got, 2), 2);
  EXPECT_EQ(std::string(got, 2), "ab");
  for (int fd : {client, server, listener, unconnected, pair[0], pair[1]}) close(fd);
}
