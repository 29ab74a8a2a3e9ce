#pragma once
// What a run needs from Trilinos (beyond Teuchos' parameter list), behind declarations that
// name no Trilinos type (docs/developer.md, "Start-up"). Two definitions: trilinos_parts.cpp
// (Tpetra, NOX, LOCA, Anasazi: the executable traverse-trilinos and the tests) and
// trilinos_absent.cpp (the executable traverse, which links no Trilinos solver library and
// hands every run that needs one over to traverse-trilinos before it starts: main.cpp,
// needs_trilinos; its definitions throw std::logic_error if reached anyway).
#include <mpi.h>

#include "traverse/core/param_list.hpp"

#include <memory>
#include <string>

#include "traverse/rod/rod_model.hpp"
#include "traverse/rod/rod_state.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/solver/block_static_start.hpp"
#include "traverse/solver/rod_stepper.hpp"

namespace traverse::app {

/// Whether this executable has the Trilinos parts (false: traverse, true: traverse-trilinos).
bool has_trilinos();

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
std::unique_ptr<solver::RodStepper> distributed_stepper(const rod::RodModel& model, const ParamList& solver,
                                                        MPI_Comm comm);

/// solver::solve_static_start over `comm` (collective).
solver::StaticStart distributed_static_start(const rod::StaticModel& m, const ParamList& solver,
                                             MPI_Comm comm);

/// initial_state: arch: the scene's rod formed into the arch (solver::form_arch, collective), as
/// the dynamic state at rest on every rank; `description` says what was done. Throws
/// std::runtime_error saying which stage failed.
rod::RodState arch_start(const scene::Scene& sc, const ParamList& solver, MPI_Comm comm,
                         std::string& description);

}  // namespace traverse::app
