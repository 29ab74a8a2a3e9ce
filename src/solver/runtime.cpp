#include "traverse/solver/runtime.hpp"

#include <Kokkos_Core.hpp>

namespace traverse::solver {

namespace {
bool started_here = false;
}  // namespace

void start_runtime() {
  if (Kokkos::is_initialized()) return;
  Kokkos::initialize();
  started_here = true;
}

void finish_runtime() {
  if (!started_here) return;
  if (Kokkos::is_initialized()) Kokkos::finalize();
  started_here = false;
}

}  // namespace traverse::solver
