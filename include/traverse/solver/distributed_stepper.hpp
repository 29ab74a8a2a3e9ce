#pragma once
// Time stepper of the rod over MPI ranks: holds the RodModel, this rank's nodes (owned plus
// one ghost each side), the Newton solver and everything reused across steps (mesh maps and
// graph, the W matrix, the linear solver and the preconditioner object). A step that Newton
// cannot solve is halved (up to "Max Subdivision Depth" times); if it still fails,
// StepFailure is thrown and the state is left as it was before the step.
//
// Only Teuchos (comm, parameter list) and the rod kernels appear here; Trilinos solver
// headers stay in the .cpp files.
#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "traverse/rod/planar.hpp"
#include "traverse/rod/rod_kernels.hpp"
#include "traverse/solver/newton_report.hpp"
#include "traverse/solver/step_failure.hpp"

namespace traverse::solver {

/// What one call of DistributedStepper::step did.
struct StepReport {
  int substeps = 0;           ///< Newton solves that converged (1 when not subdivided)
  int max_depth = 0;          ///< deepest subdivision used (0 = none)
  int failed_attempts = 0;    ///< Newton solves that failed and were subdivided
  int newton_iterations = 0;  ///< summed over all attempts
  int linear_iterations = 0;  ///< summed over all attempts
  NewtonReport last;          ///< the last converged Newton solve
};

/// Thrown by DistributedStepper::step on the planar path when the converged state's
/// out-of-plane residual (the rows the planar system drops) exceeds the Newton residual
/// tolerance: the problem was not reflection-symmetric after all. The state is unchanged.
class PlanarityLost : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// Counts of preconditioner set-up work (zero without an Ifpack2 preconditioner).
struct ReuseCounters {
  int preconditioners_created = 0;
  int preconditioner_initializations = 0;  ///< symbolic set-ups
  int preconditioner_computations = 0;     ///< numeric set-ups
  int jacobian_evaluations = 0;
  int residual_evaluations = 0;
  /// Wall time [s] spent in the kernel evaluation and the assembly of f and W (this rank).
  double assembly_seconds = 0.0;
  /// Wall time [s] spent setting up the linear solver: preconditioner initialize/compute, or
  /// the direct solver's factorisations when it runs through the reusing KLU2 path (this rank).
  double linear_setup_seconds = 0.0;
  int jacobian_reuses = 0;          ///< W requests answered with the kept W (Jacobian Reuse)
  int full_newton_retries = 0;      ///< solves redone with full Newton after a kept W failed
  /// KLU2 through the reusing path ("Direct Solver Path: Reuse Symbolic", 1 rank); zero
  /// otherwise (Stratimikos' adapter does not report them).
  int symbolic_factorizations = 0;
  int numeric_factorizations = 0;
};

class DistributedStepper {
 public:
  /// `params`: see solver_parameters.hpp (validated here; throws std::invalid_argument).
  /// The state starts as the straight rest state at t = 0; call set_state to change it.
  DistributedStepper(rod::RodModel model, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                     const Teuchos::ParameterList& params = Teuchos::ParameterList());
  ~DistributedStepper();
  DistributedStepper(const DistributedStepper&) = delete;
  DistributedStepper& operator=(const DistributedStepper&) = delete;

  /// Every rank passes the same full state (N + 1 nodes); each keeps its nodes and ghosts.
  void set_state(const rod::RodState& full);
  /// The same from this rank's piece of a state: nodes first_node .. first_node +
  /// piece.nodes.size() - 1, which must cover first_ghosted_node() .. (+ num_ghosted_nodes()).
  void set_state(const rod::RodState& piece, int first_node);
  /// This rank's nodes and one ghost on each side where there is one (the same on both paths).
  int first_ghosted_node() const;
  int num_ghosted_nodes() const;

  /// Planar fast path (collective): with a symmetry (from rod::check_planar on the model and
  /// the current state) the steps solve the in-plane system only (6 unknowns per node, or 12
  /// with carried ys); null returns to the 3D path. Rebuilds the mesh maps, W, the linear and
  /// the Newton solver; keeps the state (always stored in full 12-unknown node form). The
  /// caller is responsible for the symmetry holding; a step whose converged out-of-plane
  /// residual exceeds the residual tolerance throws PlanarityLost.
  void set_planar(const rod::PlanarSymmetry* symmetry);
  bool planar() const;
  /// The symmetry in use (null on the 3D path).
  const rod::PlanarSymmetry* planar_symmetry() const;
  /// Unknowns per node of the system solved (12 or 24 in 3D, 6 or 12 planar).
  int unknowns_per_node() const;
  /// e.g. "planar (6 unknowns per node, plane normal (1, 0, 0) = d1)" or "3D (12 unknowns per node)".
  std::string path_description() const;
  /// Advance by dt [s] (collective). Throws StepFailure (state unchanged) when it fails.
  StepReport step(double dt);
  /// Adaptive stepping (collective): one Newton solve of length dt, never subdivided. True when
  /// it converged (the state is at t + dt; undo_step() returns to t), false when it did not
  /// (the state is unchanged). Throws PlanarityLost as step() does.
  bool try_step(double dt, StepReport& report);
  /// Back to the state before the last successful try_step (only once per step).
  void undo_step();
  /// Solves the last successful try_step again (collective): the same old level and dt,
  /// Newton starting from that solve's solution. For loads that changed since (a coupled
  /// mass's path within the step: rod::CoupledRodStepper). True when it converged (the state
  /// is the new solution; undo_step and redo_step still apply), false when it did not (the
  /// state is back at the step's start). Throws PlanarityLost as step() does.
  bool redo_step(StepReport& report);
  /// This rank's ghosted nodes and the time, for set_state(piece, first_ghosted_node()).
  rod::RodState ghosted_piece() const;

  double time() const;  ///< [s]
  const rod::RodModel& model() const;
  int first_owned_node() const;
  int num_owned_nodes() const;
  /// Owned node k (0 <= k < num_owned_nodes()), i.e. global node first_owned_node() + k.
  const rod::RodNode& owned_node(int k) const;
  /// The full state, replicated on every rank (collective).
  rod::RodState gather_state() const;

  /// The linear solver that runs, e.g. "Amesos2 KLU2 (direct)", and whether the configured
  /// one was rerouted (Amesos2 on 2+ ranks).
  const std::string& resolved_linear_solver() const;
  const std::string& requested_linear_solver() const;
  bool linear_solver_rerouted() const;

  /// "block storage" when the steps use BlockNewton (one rank, block-tridiagonal LU: the same
  /// iterates as NOX), "NOX" otherwise.
  std::string newton_implementation() const;
  /// Newton report of the last solve attempted (converged or not).
  const NewtonReport& last_newton_report() const;
  ReuseCounters reuse_counters() const;
  /// Identity of the reused objects (for tests): the W matrix and its graph.
  const void* jacobian_address() const;
  const void* graph_address() const;
  const void* mesh_graph_address() const;
  /// The validated parameters in use.
  const Teuchos::ParameterList& parameters() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace traverse::solver
