// The executable traverse links no Trilinos solver library (trilinos_parts.hpp): main hands
// every run that needs one over to traverse-trilinos before it starts (needs_trilinos), so
// nothing here is reached; if it were, that is a bug, said as such.
#include <stdexcept>
#include <string>

#include "run.hpp"
#include "trilinos_parts.hpp"

namespace traverse::app {

namespace {
[[noreturn]] void absent(const std::string& what) {
  throw std::logic_error("traverse: " + what + " needs Trilinos, which this executable does not load "
                         "(traverse-trilinos runs it; main should have handed the run over)");
}
}  // namespace

bool has_trilinos() { return false; }

struct TpetraScope::Impl {};
TpetraScope::TpetraScope(MPI_Comm) { absent("Tpetra"); }
TpetraScope::~TpetraScope() = default;

void finish_solver_runtime() {}

std::unique_ptr<solver::RodStepper> distributed_stepper(const rod::RodModel&, const ParamList&, MPI_Comm) {
  absent("the distributed rod stepper");
}

solver::StaticStart distributed_static_start(const rod::StaticModel&, const ParamList&, MPI_Comm) {
  absent("the distributed static start");
}

rod::RodState arch_start(const scene::Scene&, const ParamList&, MPI_Comm, std::string&) {
  absent("the arch formation");
}

void run_statics(const scene::Scene&, const RunOptions&, MPI_Comm) { absent("continuation"); }

}  // namespace traverse::app
