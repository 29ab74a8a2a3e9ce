#include "traverse/solver/linear_solver_choice.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "traverse/solver/solver_parameters.hpp"

namespace traverse::solver {

namespace {

using Teuchos::ParameterList;

// The string `key` of `pl`, or `fallback` when there is none (not stored, unlike
// ParameterList::get with a default).
std::string get_or(const ParameterList& pl, const std::string& key, const std::string& fallback) {
  const std::string* v = pl.getPtr<std::string>(key);
  return v ? *v : fallback;
}

constexpr int kBlockTridiagonalRestart = 40;

const char* const kSchwarzText = "Ifpack2 SCHWARZ (overlap 1, Amesos2 KLU2 subdomains)";

ParameterList amesos2_list() {
  ParameterList s("Stratimikos");
  s.set("Linear Solver Type", "Amesos2");
  s.sublist("Linear Solver Types").sublist("Amesos2").set("Solver Type", "KLU2");
  s.set("Preconditioner Type", "None");
  return s;
}

ParameterList gmres_list(const ParameterList& p, const std::string& prec, std::string& text) {
  ParameterList s("Stratimikos");
  s.set("Linear Solver Type", "Belos");
  auto& belos = s.sublist("Linear Solver Types").sublist("Belos");
  belos.set("Solver Type", "Pseudo Block GMRES");
  auto& g = belos.sublist("Solver Types").sublist("Pseudo Block GMRES");
  g.set("Convergence Tolerance", p.get<double>("Linear Tolerance"));
  g.set("Maximum Iterations", p.get<int>("Max Linear Iterations"));
  g.set("Num Blocks", p.get<int>("Krylov Subspace Size"));
  text = "Belos GMRES";
  if (prec == "None") {
    s.set("Preconditioner Type", "None");
    text += " (no preconditioner)";
    return s;
  }
  s.set("Preconditioner Type", "Ifpack2");
  auto& ip = s.sublist("Preconditioner Types").sublist("Ifpack2");
  auto& settings = ip.sublist("Ifpack2 Settings");
  if (prec == "SCHWARZ") {
    ip.set("Prec Type", "SCHWARZ");
    ip.set("Overlap", 1);
    settings.set("schwarz: overlap level", 1);
    settings.set("subdomain solver name", "AMESOS2");
    auto& sub = settings.sublist("subdomain solver parameters");
    sub.set("Amesos2 solver name", "klu2");
    sub.sublist("Amesos2");
    text += std::string(" + ") + kSchwarzText;
  } else if (prec == "BLOCK_TRIDIAGONAL") {
    // traverse's block-tridiagonal LU (block_tridiagonal_preconditioner.hpp): exact, also
    // across ranks (GMRES converges in one iteration).
    ip.set("Prec Type", "BLOCK_TRIDIAGONAL");
    // One iteration: a long restart cycle only costs memory (the Krylov basis is allocated up
    // front: 200 vectors are 19 kB per node of the rod).
    g.set("Num Blocks", std::min(p.get<int>("Krylov Subspace Size"), kBlockTridiagonalRestart));
    text += " + block-tridiagonal LU";
  } else if (prec == "ILUT") {
    ip.set("Prec Type", "ILUT");
    settings.set("fact: ilut level-of-fill", 3.0);
    settings.set("fact: drop tolerance", 0.0);
    settings.set("fact: absolute threshold", 1e-4);
    text += " + Ifpack2 ILUT (fill 3, no drop, diagonal shift 1e-4)";
  } else if (prec == "RILUK") {
    ip.set("Prec Type", "RILUK");
    settings.set("fact: iluk level-of-fill", 2);
    settings.set("fact: absolute threshold", 1e-4);
    text += " + Ifpack2 RILUK (level 2, diagonal shift 1e-4)";
  } else {
    throw std::invalid_argument("rod solver parameters: unknown 'Preconditioner' '" + prec + "'");
  }
  return s;
}

std::string describe_pass_through(const ParameterList& s) {
  const std::string lst = get_or(s, "Linear Solver Type", "Amesos");
  std::string text = "Stratimikos " + lst;
  if (s.isSublist("Linear Solver Types") && s.sublist("Linear Solver Types").isSublist(lst)) {
    const auto& sub = s.sublist("Linear Solver Types").sublist(lst);
    if (sub.isType<std::string>("Solver Type")) text += " " + sub.get<std::string>("Solver Type");
  }
  const std::string pt = get_or(s, "Preconditioner Type", "ML");
  text += " + " + pt;
  if (s.isSublist("Preconditioner Types") && s.sublist("Preconditioner Types").isSublist(pt)) {
    const auto& sub = s.sublist("Preconditioner Types").sublist(pt);
    if (sub.isType<std::string>("Prec Type")) text += " " + sub.get<std::string>("Prec Type");
  }
  return text;
}

}  // namespace

LinearSolverChoice LinearSolverChoice::resolve(const ParameterList& given, int ranks, Use use) {
  const ParameterList p = validated_solver_parameters(given);
  LinearSolverChoice c;
  bool solver_is_auto = false;
  const ParameterList& pass = p.sublist("Stratimikos");
  if (pass.numParams() > 0) {
    c.stratimikos = pass;
    c.requested = describe_pass_through(pass);
  } else {
    std::string solver = p.get<std::string>("Linear Solver");
    solver_is_auto = solver == "auto" && use == Use::time_step;
    if (solver == "auto") solver = use == Use::time_step ? "auto-time-step" : ranks > 1 ? "GMRES" : "KLU2";
    if (solver == "auto-time-step") {
      c.stratimikos = gmres_list(p, "BLOCK_TRIDIAGONAL", c.requested);
    } else if (solver == "KLU2") {
      c.stratimikos = amesos2_list();
      c.requested = "Amesos2 KLU2 (direct)";
    } else {
      c.stratimikos = gmres_list(p, p.get<std::string>("Preconditioner"), c.requested);
    }
  }
  c.resolved = c.requested;
  c.linear_tolerance = p.get<double>("Linear Tolerance");
  c.block_tridiagonal = pass.numParams() == 0 && c.stratimikos.isSublist("Preconditioner Types") &&
                        c.stratimikos.sublist("Preconditioner Types").isSublist("Ifpack2") &&
                        get_or(c.stratimikos.sublist("Preconditioner Types").sublist("Ifpack2"), "Prec Type", "") ==
                            "BLOCK_TRIDIAGONAL";
  if ((ranks == 1 || solver_is_auto) && c.block_tridiagonal) {
    c.block_tridiagonal_direct = true;
    ParameterList direct("Stratimikos");
    direct.set("Linear Solver Type", std::string(kBlockTridiagonalLu));
    direct.sublist("Linear Solver Types").sublist(kBlockTridiagonalLu).set("Tolerance", c.linear_tolerance);
    direct.set("Preconditioner Type", std::string("None"));
    c.stratimikos = direct;
    c.resolved = ranks == 1 ? "block-tridiagonal LU (direct, residual-checked)"
                            : "block-tridiagonal LU (direct, exact across " + std::to_string(ranks) +
                                  " ranks through a separator system, residual-checked)";
  }
  const std::string lst = get_or(c.stratimikos, "Linear Solver Type", "Amesos");
  c.direct = lst == "Amesos2" || lst == "Amesos";
  if (lst == "Amesos2" && ranks > 1) {
    std::string which = "KLU2";
    if (c.stratimikos.isSublist("Linear Solver Types") &&
        c.stratimikos.sublist("Linear Solver Types").isSublist("Amesos2"))
      which = get_or(c.stratimikos.sublist("Linear Solver Types").sublist("Amesos2"), "Solver Type", "KLU2");
    const std::string why = "Amesos2 " + which + " returns wrong solutions on " +
                            std::to_string(ranks) + " ranks on this platform (Trilinos 13.2)";
    if (p.get<std::string>("On Broken Direct Solver") == "refuse")
      throw std::invalid_argument("rod solver parameters: linear solver '" + c.requested +
                                  "' refused: " + why +
                                  "; use 'Linear Solver: GMRES' or 'On Broken Direct Solver: reroute'");
    std::string text;
    c.stratimikos = gmres_list(p, "SCHWARZ", text);
    c.resolved = text + " [rerouted from " + c.requested + ": " + why + "]";
    c.rerouted = true;
    c.direct = false;
  }
  return c;
}

double LinearSolverChoice::memory_factor() const {
  if (block_tridiagonal) return 1.0;
  return direct ? 1.07 : 1.4;
}

}  // namespace traverse::solver
