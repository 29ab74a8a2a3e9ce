#pragma once
// Time stepper of the rod on any number of MPI ranks (a RodStepper): holds this rank's nodes
// (owned plus one ghost each side), NOX's Newton solver (newton_solver.hpp) and everything
// reused across steps (mesh maps and graph, the W matrix, the linear solver and the
// preconditioner object).
//
// Only Teuchos (comm, parameter list) and the rod kernels appear here; Trilinos solver
// headers stay in the .cpp files.
#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "traverse/solver/rod_stepper.hpp"

namespace traverse::solver {

class DistributedStepper : public RodStepper {
 public:
  /// `params`: see solver_parameters.hpp (validated here; throws std::invalid_argument).
  /// The state starts as the straight rest state at t = 0; call set_state to change it.
  DistributedStepper(rod::RodModel model, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                     const Teuchos::ParameterList& params = Teuchos::ParameterList());
  ~DistributedStepper() override;

  rod::RodState gather_state() const override;
  ReuseCounters reuse_counters() const override;
  /// Identity of the reused objects (for tests): the W matrix and its graph.
  const void* jacobian_address() const;  ///< the W operator (the same object every step)
  const void* graph_address() const;     ///< W's graph (null with block storage)
  const void* mesh_graph_address() const;

 protected:
  void rebuild() override;
  void set_old_level(std::vector<rod::RodNode> ghosted_old_nodes, const rod::StepTimes& step) override;
  const std::vector<rod::RodNode>& old_level() const override;
  NewtonReport solve_level(std::vector<VecX>& xg, std::optional<rod::InitialGuess> guess, StepReport& sr) override;
  double dropped_residual_everywhere() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace traverse::solver
