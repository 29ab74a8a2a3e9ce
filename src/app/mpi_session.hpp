#pragma once
// MPI for the commands that need it, started as cheaply as is correct (docs/developer.md,
// "Start-up"): --help, --version and, outside an MPI launcher, check and xdmf never start
// MPI; a run outside a launcher starts MPI as an isolated singleton (no daemon, no network
// transports); under mpirun/mpiexec/srun, MPI starts as the launcher configured it.
#include <mpi.h>

#include <string>
#include <utility>
#include <vector>

namespace traverse::app {

/// What the environment says about how this process was started.
struct Launch {
  bool by_launcher = false;  ///< started by mpirun, mpiexec, srun (a process-manager variable is set)
  int rank = 0;              ///< this process's rank in the launch (0 outside a launcher)
};

/// Reads the variables Open MPI, MPICH/Hydra, PMIx and Slurm set for the processes they start.
Launch launch_from_environment();

/// MPI for the lifetime of the object, when started; MPI_Finalize at the end (or finish()).
class MpiSession {
 public:
  MpiSession() = default;
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  ~MpiSession() { finish(); }

  /// Starts MPI. Outside a launcher (`launch.by_launcher` false) the Open MPI settings of a
  /// single process are set first, unless the environment sets them already: pml ob1 and
  /// btl self (no UCX or network probing), no binding, no PCI discovery by hwloc and none of
  /// its device or libxml2 plugins (HWLOC_COMPONENTS, HWLOC_PLUGINS_BLACKLIST),
  /// ess_singleton_isolated (no orted daemon) with a session directory of its own (a fresh
  /// TMPDIR/traverse-mpi-XXXXXX, removed by finish). Under Open MPI's launcher with every
  /// rank on this host: pml ob1 (shared memory, no UCX network probing), the same hwloc
  /// settings and PMIx's hash datastore (PMIX_MCA_gds), unless the environment sets them.
  ///
  /// `sweep`: MPI for a sweep only (its queue, its index rows, cases on MPI_COMM_SELF). Under
  /// Open MPI's launcher with every rank on this host, Open MPI then opens only the components
  /// that serve this (sweep_components), unless the environment selects them already.
  void start(int* argc, char*** argv, const Launch& launch, bool sweep = false);
  bool started() const { return started_; }
  /// MPI_COMM_WORLD once started; MPI_COMM_NULL (this process alone, no MPI) before.
  MPI_Comm comm() const { return started_ ? MPI_COMM_WORLD : MPI_COMM_NULL; }
  int rank() const;
  void finish();

 private:
  bool started_ = false;
  std::string session_dir_;  ///< this process's own Open MPI session directory, if made here
};

/// The Open MPI component selections a sweep's ranks set before MPI_Init under Open MPI's
/// launcher with every rank on this host, as (MCA variable, value) pairs: transports self,
/// vader (shared memory) and tcp (only if shared memory fails; 1 ms), the collectives basic,
/// self and libnbc (no tuned, han, adapt, sm or monitoring), one-sided sm (the queue's shared
/// window), and the component a rank of the launcher selects anyway in four start-up
/// frameworks (state app, errmgr default_app, shmem mmap, schizo ompi; ess and pmix the
/// launcher restricts itself); no AVX reductions, no netlink reachability, no hugetlbfs memory
/// pool. Each only if the environment does not set it.
const std::vector<std::pair<const char*, const char*>>& sweep_components();

/// Sets TCP_NODELAY on every connected TCP socket of this process whose peer is a loopback
/// address (under mpirun: the rank's connection to the launcher's PMIx server, which PMIx
/// leaves with Nagle's algorithm on); returns how many it set. MpiSession::start calls it
/// after MPI_Init under a launcher (docs/developer.md, "Start-up").
int send_control_messages_at_once();

/// Size and rank of `comm`, with MPI_COMM_NULL meaning this process alone (MPI not started).
int comm_size(MPI_Comm comm);
int comm_rank(MPI_Comm comm);

}  // namespace traverse::app
