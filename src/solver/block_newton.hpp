#pragma once
// Newton on block storage for the single-rank rod time step with the block-tridiagonal LU: the
// step's blocks (rod::StepAssembly, the same ones RodStepModel gives NOX) are written straight
// into the L, D, U blocks of each node (block_tridiagonal_factors.hpp), factorised and solved
// without Tpetra, Thyra or NOX. It repeats, operation for operation, what NOX's line-search
// Newton with a full step does with traverse's status tests (newton_solver.cpp), so the
// iterates are the same: residual at the initial guess; each iteration one factorisation, one
// solve d = J^{-1} f with the block LU's residual check and at most two refinements (as the
// block-tridiagonal direct solver does), x <- x - d, the residual at the new x; converged when
// max|f| < residual tolerance and the WRMS update test (NOX's NormWRMS: weights rtol |x_old| +
// atol) is below 1, failed at a non-finite residual or after the maximum of iterations.
// With `next_update_test` (solver key 'Update Test: auto', the default) a step whose residual
// test holds but whose last update does not pass also converges when the next Newton update
// d = J(x_k)^{-1} f(x_k) passes the WRMS test (weights rtol |x_k| + atol) and is then taken. d
// is solved without a new factorisation: the last one (of J(x_{k-1})) preconditions the
// block system's refinements against J(x_k), assembled with f(x_k) (BlockSystem::solve), and
// the test asks the same achieved tolerance <= 0.5 as NOX's. The refinements of that solve stop
// at max|f - J d| <= 1e-4 max|f| (update_test_linear_tolerance; the first solve with the last
// factorisation reaches 1e-7 to 1e-5 on the cable): d only decides the WRMS test, where 1e-4 of
// it is immaterial, and, taken, moves x by less than the update tolerances, so its error is 1e-4
// of that. So the iteration NOX's test adds
// only to see an update of round-off size costs a solve instead of a factorisation, a solve
// and an assembly. Without it the iterates are NOX's.
// Eigen and the rod kernels only.
#include "traverse/core/param_list.hpp"

#include <memory>
#include <vector>

#include "block_system.hpp"
#include "traverse/rod/step_assembly.hpp"
#include "traverse/solver/linear_solver_choice.hpp"
#include "traverse/solver/newton_report.hpp"
#include "traverse/solver/rod_stepper.hpp"

namespace traverse::solver {

struct BlockNewtonOptions {
  double residual_tolerance = 1e-8;
  double update_relative_tolerance = 1e-8;
  double update_absolute_tolerance = 1e-10;
  int max_iterations = 20;
  double linear_tolerance = 1e-12;  ///< max|f - J d| <= this max|f| after the refinements
  bool next_update_test = true;     ///< also converge on the next update's WRMS (above)
  double update_test_linear_tolerance = 1e-4;  ///< the refinements of that update's solve (above)
};

class BlockNewton {
 public:
  /// `assembly` must cover the whole rod (one rank: every node owned) and outlive this object.
  BlockNewton(const rod::StepAssembly& assembly, BlockNewtonOptions options);
  ~BlockNewton();

  /// Newton from x (in: initial guess, unknowns_per_node() per node; out: the last iterate, the
  /// solution when converged) on the assembly's current old level. An exception thrown inside
  /// the kernels or the LU is reported as a failed solve (as NewtonSolver reports NOX's).
  NewtonReport solve(std::vector<double>& x);

  /// The largest dropped (out-of-plane) residual at the last residual evaluation (planar path).
  double last_dropped_residual() const { return dropped_; }
  int residual_evaluations() const { return n_f_; }
  int factorizations() const { return n_lu_; }
  double assembly_seconds() const { return t_asm_; }
  double factorization_seconds() const { return t_lu_; }

 private:
  NewtonReport iterate(std::vector<double>& x);
  /// f and the blocks at x; returns max|f| (NaN when f is not finite).
  double evaluate(const std::vector<double>& x);

  /// Whether the next Newton update from x (f and J at x assembled, the last factorisation as
  /// preconditioner) passes the WRMS test; if it does, it is applied to x and its WRMS put in
  /// `wrms` (the report's update_wrms; the iteration count and residual history stay those of
  /// the factorisations).
  bool next_update_small(std::vector<double>& x, double nf, double& wrms);

  const rod::StepAssembly& asm_;
  BlockNewtonOptions opt_;
  std::unique_ptr<BlockSystem> sys_;
  std::vector<double> d_, x_old_;
  double dropped_ = 0.0;
  int n_f_ = 0, n_lu_ = 0;
  double t_asm_ = 0.0, t_lu_ = 0.0;
};

/// The options of the time step's Newton from its parameters (`newton`: validated, with the
/// planar path's update tolerances: RodStepper::newton_params) and the linear solver's tolerance.
BlockNewtonOptions block_newton_options(const ParamList& newton, const LinearSolverChoice& choice);

/// Adds what `b` counted to the counters of a stepper.
void add_block_newton_counters(const BlockNewton& b, ReuseCounters& c);

}  // namespace traverse::solver
