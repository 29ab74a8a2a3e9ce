// What a run asks of the solver module (solver_access.hpp).
#include "traverse/setup/solver_access.hpp"

#include <Teuchos_DefaultMpiComm.hpp>
#include <Tpetra_Core.hpp>

#include <optional>
#include <sstream>
#include <stdexcept>

#include "traverse/setup/arch_start.hpp"
#include "traverse/setup/rod_setup.hpp"
#include "traverse/core/numerics_error.hpp"
#include "traverse/setup/run_checks.hpp"
#include "traverse/core/comm.hpp"
#include "traverse/solver/distributed_stepper.hpp"
#include "traverse/solver/runtime.hpp"
#include "traverse/solver/static_start.hpp"

namespace traverse::setup {

namespace {
Teuchos::RCP<const Teuchos::Comm<int>> teuchos_comm(MPI_Comm comm) { return Teuchos::rcp(new Teuchos::MpiComm<int>(comm)); }
}  // namespace

struct TpetraScope::Impl {
  explicit Impl(MPI_Comm comm) {
    solver::start_runtime();
    guard.emplace(&no_argc, &no_argv, comm);
  }
  int no_argc = 0;
  char** no_argv = nullptr;
  std::optional<Tpetra::ScopeGuard> guard;
};

TpetraScope::TpetraScope(MPI_Comm comm) : impl_(std::make_unique<Impl>(comm)) {}
TpetraScope::~TpetraScope() = default;

void finish_solver_runtime() { solver::finish_runtime(); }

std::unique_ptr<solver::RodStepper> distributed_stepper(const rod::RodModel& model, const Teuchos::ParameterList& solver,
                                                        MPI_Comm comm) {
  return std::make_unique<solver::DistributedStepper>(model, teuchos_comm(comm), solver);
}

solver::StaticStart distributed_static_start(const rod::StaticModel& m, const Teuchos::ParameterList& solver,
                                             MPI_Comm comm) {
  return solver::solve_static_start(m, teuchos_comm(comm), solver);
}

solver::ArchFormation form_arch(const scene::Scene& sc, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                const Teuchos::ParameterList& solver_params) {
  solver::ArchOptions o;
  o.length = sc.rod.length;
  o.num_cells = sc.mesh.nodes - 1;
  o.end_distance = sc.initial_state.end_to_end;
  o.gravity = sc.gravity;
  o.solver = solver_params;
  solver::ArchFormation arch = solver::form_arch(rod_properties(sc.rod), o, comm);
  if (!arch.ok) throw std::runtime_error("arch formation: " + arch.message);
  return arch;
}

std::string arch_summary(const solver::ArchFormation& arch) {
  std::ostringstream os;
  os << "arch formed: Euler load " << arch.euler_load << " N; end load " << arch.forming_load
     << " N when the ends passed " << arch.problem.value(rod::StaticParameter::end_position)
     << " m apart, pinned there; gravity raised to " << -arch.problem.gravity.y() << " m/s^2";
  return os.str();
}

namespace {

// The last arch formed in this process and what it depends on: the cases of a sweep that
// vary the load, the speed or the time numerics form the same arch, which is then reused
// (the formation is deterministic: the same state bit for bit). Only the problem, the state
// and the numbers of the summary are kept, not the continuation branches.
struct FormedArch {
  std::string key;
  solver::ArchFormation arch;
};

std::string arch_key(const scene::Scene& sc, const Teuchos::ParameterList& solver, MPI_Comm comm) {
  std::ostringstream os;
  os << arch_scene_key(sc) << ' ' << par::size(comm) << '\n';
  // Values only: the flags (used, default) change as the list is read.
  solver.print(os, Teuchos::ParameterList::PrintOptions().showFlags(false));
  return os.str();
}

}  // namespace

rod::RodState arch_start(const scene::Scene& sc, const Teuchos::ParameterList& solver, MPI_Comm comm,
                         std::string& description) {
  const auto tcomm = teuchos_comm(comm);
  static std::optional<FormedArch> last;
  const std::string key = arch_key(sc, solver, comm);
  const bool reused = last && last->key == key;
  if (!reused) {
    last.reset();
    solver::ArchFormation formed = form_arch(sc, tcomm, solver);
    formed.buckling = formed.forming = formed.loading = {};
    last = FormedArch{key, std::move(formed)};
  }
  const solver::ArchFormation& arch = last->arch;
  description = arch_summary(arch) + (reused ? " (formed earlier in this process, reused)" : "");
  // initial_state.loaded: the start in equilibrium with the prescribed load on the arch at
  // t = 0 (as a static start is), solved over the ranks.
  return arch_dynamic_start(
      sc, arch.problem, arch.state,
      [&](const rod::StaticProblem& pr, std::vector<rod::StaticNode>& state) {
        const solver::StaticSolveReport s = solver::static_solve(pr, state, tcomm, solver);
        rod::StaticReport r;
        r.converged = s.converged;
        r.iterations = s.iterations;
        r.message = s.message;
        return r;
      },
      description);
}

}  // namespace traverse::setup
