#pragma once
// The rod's time stepper as the run driver sees it: the state of this rank's nodes (owned
// plus one ghost each side), the step with its subdivision, the adaptive loop's try / undo /
// redo, and the path (planar or 3D). What the steps are solved with (Tpetra, NOX and the
// linear solver) is DistributedStepper's (distributed_stepper.hpp); this class holds the step
// logic and names no Trilinos type but the parameter list.
#include <Teuchos_ParameterList.hpp>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "traverse/rod/planar.hpp"
#include "traverse/rod/rod_kernels.hpp"
#include "traverse/solver/linear_solver_choice.hpp"
#include "traverse/solver/newton_report.hpp"
#include "traverse/solver/solver_parameters.hpp"
#include "traverse/solver/step_failure.hpp"

namespace traverse::solver {

/// What one call of RodStepper::step did.
struct StepReport {
  int substeps = 0;           ///< Newton solves that converged (1 when not subdivided)
  int max_depth = 0;          ///< deepest subdivision used (0 = none)
  int failed_attempts = 0;    ///< Newton solves that failed and were subdivided
  /// Newton solves that failed from the blended guess and were solved again from the old level
  /// ('Initial Guess: auto'); their iterations are in newton_iterations
  int guess_retries = 0;
  int newton_iterations = 0;  ///< summed over all attempts
  int linear_iterations = 0;  ///< summed over all attempts
  NewtonReport last;          ///< the last converged Newton solve
};

/// Thrown by RodStepper::step on the planar path when the converged state's out-of-plane
/// residual (the rows the planar system drops) exceeds the Newton residual tolerance: the
/// problem was not reflection-symmetric after all. The state is unchanged.
class PlanarityLost : public time::StepFailed {
 public:
  using time::StepFailed::StepFailed;
};

/// Counts of preconditioner set-up work (zero without an Ifpack2 preconditioner).
struct ReuseCounters {
  int preconditioners_created = 0;
  int preconditioner_initializations = 0;  ///< symbolic set-ups
  int preconditioner_computations = 0;     ///< numeric set-ups
  int jacobian_evaluations = 0;  ///< W requests
  int residual_evaluations = 0;
  /// Evaluations that computed W (one per W request at a new iterate; a residual evaluation
  /// fills W too, except at the iterate where the last solve converged).
  long jacobian_fills = 0;
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

class RodStepper {
 public:
  virtual ~RodStepper();
  RodStepper(const RodStepper&) = delete;
  RodStepper& operator=(const RodStepper&) = delete;

  /// Every rank passes the same full state (N + 1 nodes); each keeps its nodes and ghosts.
  void set_state(const rod::RodState& full);
  /// The same from this rank's piece of a state: nodes first_node .. first_node +
  /// piece.nodes.size() - 1, which must cover first_ghosted_node() .. (+ num_ghosted_nodes()).
  void set_state(const rod::RodState& piece, int first_node);
  /// This rank's nodes and one ghost on each side where there is one (the same on both paths).
  int first_ghosted_node() const { return g0_; }
  int num_ghosted_nodes() const { return ng_; }
  int first_owned_node() const { return o0_; }
  int num_owned_nodes() const { return no_; }
  /// Owned node k (0 <= k < num_owned_nodes()), i.e. global node first_owned_node() + k.
  const rod::RodNode& owned_node(int k) const;
  /// This rank's ghosted nodes and the time, for set_state(piece, first_ghosted_node()).
  rod::RodState ghosted_piece() const;
  /// The full state, replicated on every rank (collective).
  virtual rod::RodState gather_state() const = 0;

  /// Planar fast path (collective): with a symmetry (from rod::check_planar on the model and
  /// the current state) the steps solve the in-plane system only (6 unknowns per node, or 12
  /// with carried ys); null returns to the 3D path. Rebuilds what the steps are solved with;
  /// keeps the state (always stored in full 12-unknown node form). The caller is responsible
  /// for the symmetry holding; a step whose converged out-of-plane residual exceeds the
  /// residual tolerance throws PlanarityLost.
  void set_planar(const rod::PlanarSymmetry* symmetry);
  bool planar() const { return planar_ != nullptr; }
  /// The symmetry in use (null on the 3D path).
  const rod::PlanarSymmetry* planar_symmetry() const { return planar_ ? &planar_->symmetry() : nullptr; }
  /// Unknowns per node of the system solved (12 or 24 in 3D, 6 or 12 planar).
  int unknowns_per_node() const {
    return planar_ ? planar_->unknowns_per_node() : model_->unknowns_per_node();
  }
  /// e.g. "planar (6 unknowns per node, plane normal (1, 0, 0) = d1)" or "3D (12 unknowns per node)".
  std::string path_description() const;

  /// Advance by dt [s] (collective): a step Newton cannot solve is halved (up to "Max
  /// Subdivision Depth" times); if it still fails, StepFailure is thrown and the state is
  /// left as it was before the step.
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

  double time() const { return t_; }  ///< [s]
  const rod::RodModel& model() const { return *model_; }

  /// The linear solver that runs, e.g. "Amesos2 KLU2 (direct)", and whether the configured
  /// one was rerouted (Amesos2 on 2+ ranks).
  const std::string& resolved_linear_solver() const { return choice_.resolved; }
  const std::string& requested_linear_solver() const { return choice_.requested; }
  bool linear_solver_rerouted() const { return choice_.rerouted; }
  /// Newton report of the last solve attempted (converged or not).
  const NewtonReport& last_newton_report() const { return last_; }
  virtual ReuseCounters reuse_counters() const = 0;
  /// The validated parameters in use.
  const Teuchos::ParameterList& parameters() const { return params_; }

 protected:
  /// Checks the end conditions, validates `params` (std::invalid_argument), resolves the
  /// linear solver for `ranks` ranks (notice on rank 0 when rerouted and "Verbose").
  RodStepper(rod::RodModel model, const Teuchos::ParameterList& params, int ranks, int rank);
  /// The concrete stepper's partition (before the first set_state).
  void set_partition(int first_ghosted, int num_ghosted, int first_owned, int num_owned);
  const std::shared_ptr<const rod::RodModel>& shared_model() const { return model_; }
  const std::shared_ptr<const rod::PlanarReduction>& planar_reduction() const { return planar_; }
  const LinearSolverChoice& choice() const { return choice_; }
  std::vector<rod::RodNode>& nodes() { return nodes_; }
  /// The Newton parameters. Planar path: the WRMS update test over the in-plane unknowns only
  /// (n / 2) gives a norm sqrt(2) larger for the same updates, so both update tolerances are
  /// scaled by sqrt(p / q) and the planar solve stops at the same iterate as the 3D one.
  Teuchos::ParameterList newton_params() const;

  // What the concrete stepper solves the steps with.
  /// Rebuilds the solver objects for the current path and makes the current nodes its old level.
  virtual void rebuild() = 0;
  /// The old level of a step: the ghosted nodes (moved in) and the step's times.
  virtual void set_old_level(std::vector<rod::RodNode> ghosted_old_nodes, const rod::StepTimes& step) = 0;
  virtual const std::vector<rod::RodNode>& old_level() const = 0;
  /// Newton on the old level from `guess` (rod::StepAssembly::initial_guess; none: from the
  /// unknowns of the last solve, a redo); the converged (or last) iterate's ghosted full
  /// unknown blocks in xg. May solve twice (a modified Newton redone in full): `sr` gets every
  /// iteration.
  virtual NewtonReport solve_level(std::vector<VecX>& xg, std::optional<rod::InitialGuess> guess, StepReport& sr) = 0;
  /// The largest dropped (out-of-plane) residual of the last solve, over all ranks (collective).
  virtual double dropped_residual_everywhere() const = 0;

 private:
  void check_planarity(double t0, double dt) const;
  bool attempt(double t0, double dt, StepReport& sr, bool warm = false);
  void advance(double t0, double dt, int depth, StepReport& sr, double t_step, double dt_step,
               std::vector<rod::RodNode>* saved = nullptr);

  std::shared_ptr<const rod::RodModel> model_;
  Teuchos::ParameterList params_;
  LinearSolverChoice choice_;
  std::shared_ptr<const rod::PlanarReduction> planar_;  ///< null on the 3D path
  int g0_ = 0, ng_ = 0, o0_ = 0, no_ = 0;
  std::vector<rod::RodNode> nodes_;  ///< ghosted range, current level
  std::vector<VecX> xg_;             ///< the unknowns a step's solve returns (attempt)
  double t_ = 0.0;
  NewtonReport last_;
  int max_depth_ = 4;
  rod::InitialGuess guess_ = rod::InitialGuess::blend;  ///< solver key 'Initial Guess' (attempt)
  double planar_tolerance_ = 1e-8;  ///< largest dropped residual accepted at a converged iterate
  double undo_time_ = 0.0;          ///< try_step: the time before the last successful step
  double undo_dt_ = 0.0;            ///< and its length
  bool undo_ready_ = false;
};

/// The peak memory of a rod's time stepping per owned node [bytes] with the block-tridiagonal
/// LU, by unknowns per node (6: the planar path; 12: the 3D path; 24: scheme.rho_inf_space < 1,
/// the space derivatives unknowns too): the cell blocks, the Jacobian, the LU's factors, NOX's
/// vectors and the levels kept. Measured as the peak resident memory at 2 x 10^4 nodes less the
/// program's; what the stepper keeps per node and this figure change together
/// (docs/reliability.md "Limits", checked by test_limits).
double time_step_bytes_per_node(int unknowns);

}  // namespace traverse::solver
