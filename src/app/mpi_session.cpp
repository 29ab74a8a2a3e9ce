#include "mpi_session.hpp"

#include <cstdlib>
#include <initializer_list>

#include "traverse/core/comm.hpp"

namespace traverse::app {

namespace {

// The first of `names` set in the environment, or nullptr.
const char* first_set(std::initializer_list<const char*> names) {
  for (const char* n : names)
    if (const char* v = std::getenv(n)) return v;
  return nullptr;
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

void MpiSession::start(int* argc, char*** argv) {
  if (started_) return;
  MPI_Init(argc, argv);
  started_ = true;
}

int MpiSession::rank() const { return comm_rank(comm()); }

void MpiSession::finish() {
  if (!started_) return;
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!finalized) MPI_Finalize();
  started_ = false;
}

int comm_size(MPI_Comm comm) { return par::size(comm); }

int comm_rank(MPI_Comm comm) { return par::rank(comm); }

}  // namespace traverse::app
