#include "traverse/solver/solver_parameters.hpp"

#include <Teuchos_StandardParameterEntryValidators.hpp>
#include <stdexcept>

namespace traverse::solver {

Teuchos::RCP<const Teuchos::ParameterList> valid_solver_parameters() {
  static Teuchos::RCP<const Teuchos::ParameterList> valid = [] {
    using Teuchos::tuple;
    auto pl = Teuchos::rcp(new Teuchos::ParameterList("Rod Solver"));
    Teuchos::setStringToIntegralParameter<int>(
        "Linear Solver", "auto",
        "Linear solver: auto (rod time step: the block-tridiagonal LU, direct on any rank count; "
        "statics: KLU2 on 1 rank, GMRES + ILUT on more), KLU2 (Amesos2 direct), GMRES (Belos)",
        tuple<std::string>("auto", "KLU2", "GMRES"), pl.get());
    Teuchos::setStringToIntegralParameter<int>(
        "Preconditioner", "SCHWARZ",
        "Ifpack2 preconditioner of GMRES: SCHWARZ (overlap 1, KLU2 subdomains), BLOCK_TRIDIAGONAL "
        "(block-tridiagonal LU, exact also across ranks: GMRES stops after one iteration), "
        "ILUT, RILUK, None",
        tuple<std::string>("SCHWARZ", "BLOCK_TRIDIAGONAL", "ILUT", "RILUK", "None"), pl.get());
    pl->set("Linear Tolerance", 1e-12, "Relative residual reduction of each Krylov solve");
    pl->set("Max Linear Iterations", 500, "Maximum Krylov iterations per linear solve");
    pl->set("Krylov Subspace Size", 200, "GMRES restart length");
    Teuchos::setStringToIntegralParameter<int>(
        "On Broken Direct Solver", "reroute",
        "Amesos2 direct solvers are wrong on 2+ ranks on this platform: reroute to GMRES + "
        "Schwarz/KLU2 (with a notice) or refuse (throw)",
        tuple<std::string>("reroute", "refuse"), pl.get());
    pl->sublist("Stratimikos", false, "Full Stratimikos list (replaces the shortcuts when non-empty)")
        .disableRecursiveValidation();
    pl->set("Max Newton Iterations", 20, "Maximum Newton iterations per (sub)step");
    pl->set("Residual Tolerance", 1e-8, "Convergence: max |f| below this (and the update test)");
    pl->set("Update Relative Tolerance", 1e-8, "Convergence: WRMS update test rtol");
    pl->set("Update Absolute Tolerance", 1e-10, "Convergence: WRMS update test atol");
    Teuchos::setStringToIntegralParameter<int>(
        "Line Search", "Full Step", "NOX line search method",
        tuple<std::string>("Full Step", "Backtrack", "Polynomial", "More'-Thuente"), pl.get());
    pl->sublist("NOX", false, "NOX parameters merged over the defaults").disableRecursiveValidation();
    Teuchos::setStringToIntegralParameter<int>(
        "Newton Implementation", "auto",
        "Rod time step: auto = traverse's Newton on block storage where it applies (one rank, the "
        "block-tridiagonal LU, Full Step, no NOX sublist, no Jacobian Reuse; the same iterates as "
        "NOX without its overhead), NOX elsewhere; NOX = always NOX",
        tuple<std::string>("auto", "NOX"), pl.get());
    Teuchos::setStringToIntegralParameter<int>(
        "Initial Guess", "Old Level",
        "Newton's initial guess of a rod time step: Old Level = the old level's unknowns; Secant = "
        "the old level extrapolated along the last step's secant, y + dt (y - y_prev) / dt_prev "
        "(zero slope at a start): fewer iterations where the motion is smooth, but it can fail "
        "where the old level does not (docs/solver.md)",
        tuple<std::string>("Old Level", "Secant"), pl.get());
    pl->set("Max Subdivision Depth", 4, "How often a failing step may be halved (0: no retry)");
    pl->set("Verbose", true, "One-line notices on rank 0");
    pl->set("Jacobian Reuse", false,
            "Modified Newton: keep W, its factorisation or preconditioner across Newton iterations "
            "and time steps while max|f| contracts by at least 'Jacobian Reuse Contraction' per "
            "iteration; a solve that fails with a kept W is redone with full Newton");
    pl->set("Jacobian Reuse Contraction", 0.25,
            "Refresh the kept W when max|f_k| > this * max|f_{k-1}| (0 < value < 1)");
    Teuchos::setStringToIntegralParameter<int>(
        "Direct Solver Path", "Reuse Symbolic",
        "How KLU2 runs on 1 rank: Reuse Symbolic (one Amesos2 solver kept by traverse: ordering "
        "once, numeric refactorisation per new W) or Stratimikos (its Amesos2 adapter, which "
        "redoes the symbolic factorisation every time)",
        tuple<std::string>("Reuse Symbolic", "Stratimikos"), pl.get());
    return Teuchos::RCP<const Teuchos::ParameterList>(pl);
  }();
  return valid;
}

Teuchos::ParameterList validated_solver_parameters(const Teuchos::ParameterList& given) {
  Teuchos::ParameterList p = given;
  try {
    p.validateParametersAndSetDefaults(*valid_solver_parameters());
  } catch (const std::exception& e) {
    throw std::invalid_argument(std::string("rod solver parameters: ") + e.what());
  }
  auto positive = [&](const char* key, bool is_int) {
    const double v = is_int ? p.get<int>(key) : p.get<double>(key);
    if (!(v > 0.0))
      throw std::invalid_argument(std::string("rod solver parameters: '") + key +
                                  "' must be > 0, found " + std::to_string(v));
  };
  positive("Linear Tolerance", false);
  positive("Max Linear Iterations", true);
  positive("Krylov Subspace Size", true);
  positive("Max Newton Iterations", true);
  positive("Residual Tolerance", false);
  positive("Update Relative Tolerance", false);
  positive("Update Absolute Tolerance", false);
  const double c = p.get<double>("Jacobian Reuse Contraction");
  if (!(c > 0.0 && c < 1.0))
    throw std::invalid_argument("rod solver parameters: 'Jacobian Reuse Contraction' must be in (0, 1), found " +
                                std::to_string(c));
  if (p.get<int>("Max Subdivision Depth") < 0)
    throw std::invalid_argument("rod solver parameters: 'Max Subdivision Depth' must be >= 0, found " +
                                std::to_string(p.get<int>("Max Subdivision Depth")));
  return p;
}

rod::InitialGuess initial_guess_of(const Teuchos::ParameterList& validated) {
  const std::string& g = validated.get<std::string>("Initial Guess");
  return g == "Secant" ? rod::InitialGuess::secant : rod::InitialGuess::old_level;
}

}  // namespace traverse::solver
