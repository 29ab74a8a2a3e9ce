#pragma once
// The parameter list of the rod time stepper (what a scene's solver section passes through).
//
//   Linear Solver          string  "auto" | "KLU2" | "GMRES"      (default "auto": the time
//                                  step's block-tridiagonal LU, exact on any number of ranks;
//                                  statics: KLU2 on 1 rank, GMRES on more; docs/solver.md)
//   Preconditioner         string  "SCHWARZ" | "ILUT" | "RILUK" | "None" (GMRES only;
//                                  default "SCHWARZ": additive Schwarz, overlap 1, KLU2 on
//                                  each rank's block)
//   Linear Tolerance       double  relative residual of each Krylov solve (default 1e-12)
//   Max Linear Iterations  int     (default 500)
//   Krylov Subspace Size   int     GMRES restart length (default 200)
//   On Broken Direct Solver string "reroute" | "refuse" (default "reroute"): what to do when
//                                  an Amesos2 direct solver is asked for on 2+ ranks, where
//                                  it returns wrong answers on this platform
//   Stratimikos            sublist optional full Stratimikos list; when non-empty it replaces
//                                  the shortcuts above (the broken-solver rule still applies)
//   Max Newton Iterations  int     (default 20)
//   Residual Tolerance     double  max |f| for convergence (default 1e-8)
//   Update Relative Tolerance double WRMS update test rtol (default 1e-8)
//   Update Absolute Tolerance double WRMS update test atol (default 1e-10)
//   Line Search            string  NOX line search method: "Full Step" | "Backtrack" |
//                                  "Polynomial" | "More'-Thuente" (default "Full Step")
//   NOX                    sublist optional NOX parameters, merged over the defaults built
//                                  from the keys above (a user's value wins)
//   Update Test            string  "auto" | "Last Update" (default "auto"): with auto and the
//                                  block-tridiagonal LU, a step also ends when max|f| passes
//                                  and the next update (solved with the last factorisation)
//                                  passes the WRMS test (next_update_test.hpp, a NOX status
//                                  test); NOX's test (the update just taken) with the other
//                                  linear solvers and with "Last Update" (docs/solver.md)
//   Initial Guess          string  "auto" | "Old Level" | "Secant" (default "auto"): Newton's
//                                  initial guess of a time step, the old level itself or
//                                  extrapolated along the last step's secant
//                                  (rod::StepAssembly::initial_guess, docs/solver.md); auto:
//                                  extrapolated only in the entries the last step's secant
//                                  predicted well (rod::RodNode::yg), and where Newton fails
//                                  from there, the old level before the step is halved
//                                  (RodStepper::attempt)
//   Max Subdivision Depth  int     how often a failing step may be halved (default 4;
//                                  0 disables retries)
//   Verbose                bool    one-line notices on rank 0 (default true)
//   Jacobian Reuse         bool    modified Newton (default false): a Newton iteration keeps
//                                  the W already filled (and its KLU2 factors or Ifpack2
//                                  preconditioner), across iterations and time steps, while
//                                  max|f| contracts by at least the factor below per
//                                  iteration; otherwise W is refilled at the current iterate.
//                                  A solve that fails with a kept W is redone with full Newton
//                                  before the step is halved. Converged states differ from
//                                  full Newton's by up to the Newton tolerances.
//   Jacobian Reuse Contraction double in (0, 1) (default 0.25): refresh W when
//                                  max|f_k| > value * max|f_{k-1}|
//   Direct Solver Path     string  "Reuse Symbolic" | "Stratimikos" (default "Reuse
//                                  Symbolic"): KLU2 on 1 rank through traverse's own Amesos2
//                                  factory (symbolic factorisation once, numeric per new W,
//                                  none when W did not change) or through Stratimikos'
//                                  Amesos2 adapter (symbolic redone every Newton iteration).
//                                  Pass-through Stratimikos lists always use Stratimikos.
#include <Teuchos_ParameterList.hpp>

#include <string>
#include <variant>
#include <vector>

#include "traverse/rod/step_assembly.hpp"

namespace traverse::solver {

/// One key of the rod solver's list: its name, its type (the default's), its default and, for
/// a word, the words it accepts (sublists NOX and Stratimikos are not validated here: they are
/// handed to the Trilinos packages, which validate them).
struct SolverKey {
  std::string name;
  std::variant<bool, int, double, std::string> default_value;
  std::vector<std::string> words;  ///< a string key: the accepted values
  std::string doc;
};

/// Every key of the list above with its default and documentation, in that order.
const std::vector<SolverKey>& solver_keys();

/// A copy of `given` validated against solver_keys() with every default filled in (an integer
/// is accepted for a real key). Throws std::invalid_argument naming the offending key on a
/// wrong name, type or value.
Teuchos::ParameterList validated_solver_parameters(const Teuchos::ParameterList& given);

/// A scene's solver section, checked once where the scene is: validated_solver_parameters, and
/// its 'Stratimikos' sublist by check_stratimikos_list (the solver's own calls validate the
/// keys only).
Teuchos::ParameterList checked_solver_parameters(const Teuchos::ParameterList& given);

/// Hands `list` to a Stratimikos builder with traverse's factories (as the runs do) and creates
/// its linear solver and preconditioner strategies, so that a name this Trilinos does not have
/// (a solver type, an Amesos2 solver) is refused before a run starts. Throws
/// std::invalid_argument with Trilinos' message, without its source locations.
void check_stratimikos_list(const Teuchos::ParameterList& list);

/// The key 'Initial Guess' of a validated list (auto: the blend).
rod::InitialGuess initial_guess_of(const Teuchos::ParameterList& validated);

}  // namespace traverse::solver
