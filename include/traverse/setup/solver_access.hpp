#pragma once
// What a run asks of the solver module (Tpetra, NOX, LOCA), behind declarations that name no
// Trilinos type: app's other translation units compile without the Trilinos headers.
#include <mpi.h>

#include <Teuchos_ParameterList.hpp>

#include <memory>
#include <string>

#include "traverse/rod/rod_model.hpp"
#include "traverse/rod/rod_state.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/solver/static_start.hpp"
#include "traverse/solver/rod_stepper.hpp"

namespace traverse::setup {

/// Kokkos (started once, until finish_solver_runtime) and Tpetra for the lifetime of the object.
class TpetraScope {
 public:
  explicit TpetraScope(MPI_Comm comm);
  ~TpetraScope();
  TpetraScope(const TpetraScope&) = delete;
  TpetraScope& operator=(const TpetraScope&) = delete;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// solver::DistributedStepper over `comm` (collective); throws std::invalid_argument as it does.
std::unique_ptr<solver::RodStepper> distributed_stepper(const rod::RodModel& model, const Teuchos::ParameterList& solver,
                                                        MPI_Comm comm);

/// solver::solve_static_start over `comm` (collective).
solver::StaticStart distributed_static_start(const rod::StaticModel& m, const Teuchos::ParameterList& solver,
                                             MPI_Comm comm);

/// initial_state: arch: the scene's rod formed into the arch (solver::form_arch, collective), as
/// the dynamic state at rest on every rank; `description` says what was done. Throws
/// std::runtime_error saying which stage failed.
rod::RodState arch_start(const scene::Scene& sc, const Teuchos::ParameterList& solver, MPI_Comm comm,
                         std::string& description);

/// Ends what rod runs started for the whole process (Kokkos, started by the first rod run
/// and kept for the next ones, e.g. the cases of a sweep); call before MPI_Finalize.
void finish_solver_runtime();

}  // namespace traverse::setup
