#pragma once
// The process-wide runtime of the solver module (Kokkos): started by the first run that
// needs it and kept for the next runs of the same process (Kokkos can be initialised only
// once per process), ended once before MPI_Finalize.
namespace traverse::solver {

/// Starts Kokkos if it is not running (a no-op afterwards).
void start_runtime();

/// Ends Kokkos if start_runtime started it; every Tpetra object must be gone.
void finish_runtime();

}  // namespace traverse::solver
