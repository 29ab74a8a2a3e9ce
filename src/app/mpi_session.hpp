#pragma once
// MPI for the commands that need it: --help and --version never start it, check and xdmf only
// under an MPI launcher (every rank then takes part); a run and a sweep always. MPI starts as
// the installation and the launcher configure it: traverse sets none of MPI's settings.
#include <mpi.h>

namespace traverse::app {

/// What the environment says about how this process was started.
struct Launch {
  bool by_launcher = false;  ///< started by mpirun, mpiexec, srun (a process-manager variable is set)
  int rank = 0;              ///< this process's rank in the launch (0 outside a launcher)
};

/// Reads the variables Open MPI, MPICH/Hydra, PMIx and Slurm set for the processes they start,
/// so that a command that does not start MPI still lets only the first rank report.
Launch launch_from_environment();

/// MPI for the lifetime of the object, when started; MPI_Finalize at the end (or finish()).
class MpiSession {
 public:
  MpiSession() = default;
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  ~MpiSession() { finish(); }

  /// MPI_Init (once).
  void start(int* argc, char*** argv);
  bool started() const { return started_; }
  /// MPI_COMM_WORLD once started; MPI_COMM_NULL (this process alone, no MPI) before.
  MPI_Comm comm() const { return started_ ? MPI_COMM_WORLD : MPI_COMM_NULL; }
  int rank() const;
  void finish();

 private:
  bool started_ = false;
};

/// Size and rank of `comm`, with MPI_COMM_NULL meaning this process alone (MPI not started).
int comm_size(MPI_Comm comm);
int comm_rank(MPI_Comm comm);

}  // namespace traverse::app
