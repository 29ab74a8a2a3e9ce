#pragma once
// Resolution of the configured linear solver into a Stratimikos parameter list for the
// current rank count, with the platform rule: Amesos2 direct solvers give wrong answers on
// 2+ ranks here (see docs/solver.md), so they are rerouted (default) or refused.
#include <Teuchos_ParameterList.hpp>

#include <string>

namespace traverse::solver {

/// The name Stratimikos knows the block-tridiagonal LU by ("Linear Solver Type"; its sublist
/// of "Linear Solver Types" takes "Tolerance", the residual check of each solve).
inline constexpr char kBlockTridiagonalLu[] = "Block Tridiagonal LU";

struct LinearSolverChoice {
  std::string requested;   ///< what the parameters asked for, e.g. "Amesos2 KLU2"
  std::string resolved;    ///< what will run, e.g. "Belos GMRES + Ifpack2 SCHWARZ (...)"
  bool rerouted = false;   ///< true when the request was replaced by the broken-solver rule
  bool direct = false;     ///< resolved solver is a direct (Amesos2) solver
  /// The block-tridiagonal LU as the direct solver (Stratimikos' kBlockTridiagonalLu,
  /// residual-checked, exact across ranks) instead of through Belos: 'auto' for the time
  /// step on any number of ranks, and GMRES + BLOCK_TRIDIAGONAL on one rank.
  bool block_tridiagonal_direct = false;
  /// The block-tridiagonal LU solves (block_tridiagonal_direct) or preconditions GMRES.
  bool block_tridiagonal = false;
  double linear_tolerance = 1e-12;  ///< 'Linear Tolerance' (relative residual of each solve)
  Teuchos::ParameterList stratimikos{"Stratimikos"};  ///< the list handed to Stratimikos

  /// What the solver is for: 'Linear Solver: auto' means GMRES + the block-tridiagonal LU
  /// for the rod time step (its Jacobian is block tridiagonal by node with invertible Schur
  /// complements), and KLU2 on 1 rank / GMRES + Schwarz on more for statics (the static
  /// Jacobian at a straight, unloaded state has singular node blocks).
  enum class Use { time_step, statics };

  /// `params` as accepted by validated_solver_parameters (defaults filled in here too);
  /// `ranks` the communicator size. Throws std::invalid_argument when the request is refused
  /// ("On Broken Direct Solver: refuse") or names an unknown solver/preconditioner.
  static LinearSolverChoice resolve(const Teuchos::ParameterList& params, int ranks,
                                    Use use = Use::statics);

  /// The memory of the time stepping with this solver relative to the block-tridiagonal LU
  /// (time_step_bytes_per_node): 1 for it, 1.07 for a direct Amesos2 solver (its own copy of
  /// the matrix and factors), 1.4 for a Krylov method with another preconditioner (the
  /// Krylov basis, the preconditioner's matrices); measured as time_step_bytes_per_node is.
  double memory_factor() const;
};

}  // namespace traverse::solver
