#include "mpi_session.hpp"

#include <arpa/inet.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <signal.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <vector>

#include "traverse/core/comm.hpp"

namespace traverse::app {

namespace {

// The first of `names` set in the environment, or nullptr.
const char* first_set(std::initializer_list<const char*> names) {
  for (const char* n : names)
    if (const char* v = std::getenv(n)) return v;
  return nullptr;
}

constexpr const char* kSessionPrefix = "traverse-mpi-";

// Removes the session directories (under `base`) of processes that no longer exist (killed
// before they could remove their own); each holds its owner's pid in the file `owner`.
void remove_stale_sessions(const std::filesystem::path& base) {
  namespace fs = std::filesystem;
  std::error_code ec;
  for (fs::directory_iterator it(base, ec), end; !ec && it != end; it.increment(ec)) {
    if (it->path().filename().string().rfind(kSessionPrefix, 0) != 0) continue;
    std::ifstream owner(it->path() / "owner");
    long pid = 0;
    if (!(owner >> pid) || pid <= 0) continue;  // not (yet) owned: leave it alone
    if (kill(static_cast<pid_t>(pid), 0) != 0 && errno == ESRCH) {
      std::error_code ignored;
      fs::remove_all(it->path(), ignored);
    }
  }
}

// A fresh session directory of this process under TMPDIR (or /tmp); empty if none can be made.
std::string make_session_dir() {
  const char* tmp = std::getenv("TMPDIR");
  const std::string base = tmp && *tmp ? tmp : "/tmp";
  remove_stale_sessions(base);
  std::string pattern = base + "/" + kSessionPrefix + "XXXXXX";
  std::vector<char> buf(pattern.begin(), pattern.end());
  buf.push_back('\0');
  if (!mkdtemp(buf.data())) return "";
  std::ofstream(std::string(buf.data()) + "/owner") << getpid() << "\n";
  return buf.data();
}

}  // namespace

Launch launch_from_environment() {
  Launch l;
  // Open MPI's mpirun, PMIx launchers, MPICH/Hydra (PMI), Slurm's srun.
  const char* rank = first_set({"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK", "SLURM_PROCID"});
  const char* other = first_set({"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMI_FD", "PMIX_NAMESPACE", "HYDI_CONTROL_FD"});
  l.by_launcher = rank || other;
  if (rank) l.rank = std::atoi(rank);
  return l;
}

namespace {
/// Open MPI's launcher says how many ranks it started in all and on this host.
bool all_ranks_on_this_host() {
  const char* all = std::getenv("OMPI_COMM_WORLD_SIZE");
  const char* here = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE");
  return all && here && std::string(all) == here;
}
/// hwloc (which MPI_Init runs) neither reads the PCI devices nor loads its plugins for
/// devices and for XML through libxml2 (OpenCL, OpenGL with the X libraries, libpciaccess,
/// libxml2 with ICU: about 40 MB of libraries mapped and relocated); its built-in XML parser
/// still reads any topology the launcher passes. For a process whose only peers are on this
/// host. 0: a setting already made in the environment wins.
void skip_device_discovery() {
  setenv("HWLOC_COMPONENTS", "-pci,-linuxio", 0);
  setenv("HWLOC_PLUGINS_BLACKLIST", "hwloc_pci,hwloc_opencl,hwloc_gl,hwloc_xml_libxml", 0);
}

bool is_loopback(const sockaddr_storage& a) {
  if (a.ss_family == AF_INET)
    return (ntohl(reinterpret_cast<const sockaddr_in&>(a).sin_addr.s_addr) >> 24) == 127;
  if (a.ss_family == AF_INET6) {
    const in6_addr& x = reinterpret_cast<const sockaddr_in6&>(a).sin6_addr;
    return IN6_IS_ADDR_LOOPBACK(&x) || (IN6_IS_ADDR_V4MAPPED(&x) && x.s6_addr[12] == 127);
  }
  return false;
}
}  // namespace

// The launcher's PMIx server on this host talks to each rank over a loopback TCP socket
// that PMIx leaves with Nagle's algorithm on. MPI_Finalize sends it a few small messages
// in a row and waits for the answer: the second message waits for the server's delayed
// acknowledgement of the first (about 40 ms on Linux), so every run under mpirun spent
// about 50 ms in MPI_Finalize (11 ms with the sockets set to send at once). Only connected
// loopback TCP sockets are touched: they lead to processes on this host only.
int send_control_messages_at_once() {
  namespace fs = std::filesystem;
  int set = 0;
  std::error_code ec;
  for (fs::directory_iterator it("/proc/self/fd", ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    char* stop = nullptr;
    const long fd = std::strtol(name.c_str(), &stop, 10);
    if (stop == name.c_str() || *stop != '\0') continue;
    int type = 0;
    socklen_t len = sizeof type;
    if (getsockopt(static_cast<int>(fd), SOL_SOCKET, SO_TYPE, &type, &len) != 0 || type != SOCK_STREAM) continue;
    sockaddr_storage peer{};
    len = sizeof peer;
    if (getpeername(static_cast<int>(fd), reinterpret_cast<sockaddr*>(&peer), &len) != 0 || !is_loopback(peer))
      continue;
    const int one = 1;
    if (setsockopt(static_cast<int>(fd), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one) == 0) ++set;
  }
  return set;
}

const std::vector<std::pair<const char*, const char*>>& sweep_components() {
  static const std::vector<std::pair<const char*, const char*>> list = {
      {"OMPI_MCA_btl", "self,vader,tcp"}, {"OMPI_MCA_coll", "basic,self,libnbc"}, {"OMPI_MCA_osc", "sm"},
      {"OMPI_MCA_state", "app"},         {"OMPI_MCA_errmgr", "default_app"},     {"OMPI_MCA_shmem", "mmap"},
      {"OMPI_MCA_schizo", "ompi"},       {"OMPI_MCA_op", "^avx"},                {"OMPI_MCA_reachable", "^netlink"},
      {"OMPI_MCA_mpool", "^hugepage"}};
  return list;
}

void MpiSession::start(int* argc, char*** argv, const Launch& launch, bool sweep) {
  if (started_) return;
  // 0 in setenv: a setting already made in the environment wins.
  const bool alone = !launch.by_launcher, one_host = alone || all_ranks_on_this_host();
  if (one_host) {
    // Every peer on this host (Open MPI's ranks all here, or this process alone): shared
    // memory or self (pml ob1), so no UCX network probing (about 0.3 s of each launch here),
    // and no network device to place (skip_device_discovery: about 0.03 s of each MPI_Init
    // here, 1/5 of a singleton's).
    setenv("OMPI_MCA_pml", "ob1", 0);
    skip_device_discovery();
  }
  if (alone) {
    // One process: only the self transport (its only peer is itself); nothing to bind.
    setenv("OMPI_MCA_btl", "self", 0);
    setenv("OMPI_MCA_hwloc_base_binding_policy", "none", 0);
    // No daemon (it would only serve MPI_Comm_spawn, never used). Isolated singletons all
    // get the same job id, so each needs a session directory of its own (removed in finish).
    if (!std::getenv("OMPI_MCA_ess_singleton_isolated") && !std::getenv("OMPI_MCA_orte_tmpdir_base")) {
      session_dir_ = make_session_dir();
      if (!session_dir_.empty()) {
        setenv("OMPI_MCA_orte_tmpdir_base", session_dir_.c_str(), 1);
        setenv("OMPI_MCA_ess_singleton_isolated", "1", 1);
      }
    }
  } else if (one_host) {
    // Under the launcher: the few keys of a few ranks come from its PMIx server over its
    // socket (gds hash) instead of by mapping its shared-memory store (ds21): another 0.03 s
    // of each rank's MPI_Init here.
    setenv("PMIX_MCA_gds", "hash", 0);
    // A sweep's ranks use MPI for little (its queue, its index rows; each case on
    // MPI_COMM_SELF): Open MPI need not open (dlopen, register, select) the components for
    // networks and for collectives over many ranks: 24 components loaded instead of 46, a
    // trivial 2-rank sweep 0.006-0.018 s faster here, a 1-rank one 0.008-0.011 s
    // (docs/benchmarks.md, "A sweep's Open MPI components").
    if (sweep)
      for (const auto& [name, value] : sweep_components()) setenv(name, value, 0);
  }
  MPI_Init(argc, argv);
  started_ = true;
  if (launch.by_launcher) send_control_messages_at_once();
}

int MpiSession::rank() const { return comm_rank(comm()); }

void MpiSession::finish() {
  if (!started_) return;
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
  started_ = false;
  if (!session_dir_.empty()) {
    std::error_code ignored;
    std::filesystem::remove_all(session_dir_, ignored);
    session_dir_.clear();
  }
}

int comm_size(MPI_Comm comm) { return par::size(comm); }

int comm_rank(MPI_Comm comm) { return par::rank(comm); }

}  // namespace traverse::app
