#include "traverse/solver/solver_parameters.hpp"

#include <algorithm>
#include <iterator>
#include <stdexcept>
#include <type_traits>
#include <variant>

namespace traverse::solver {

const std::vector<SolverKey>& solver_keys() {
  static const std::vector<SolverKey> keys = {
      {"Linear Solver", std::string("auto"), {"auto", "KLU2", "GMRES"},
       "Linear solver: auto (rod time step: the block-tridiagonal LU, direct on any rank count; "
       "statics: KLU2 on 1 rank, GMRES + ILUT on more), KLU2 (Amesos2 direct), GMRES (Belos)"},
      {"Preconditioner", std::string("SCHWARZ"), {"SCHWARZ", "BLOCK_TRIDIAGONAL", "ILUT", "RILUK", "None"},
       "Ifpack2 preconditioner of GMRES: SCHWARZ (overlap 1, KLU2 subdomains), BLOCK_TRIDIAGONAL "
       "(block-tridiagonal LU, exact also across ranks: GMRES stops after one iteration), "
       "ILUT, RILUK, None"},
      {"Linear Tolerance", 1e-12, {}, "Relative residual reduction of each Krylov solve"},
      {"Max Linear Iterations", 500, {}, "Maximum Krylov iterations per linear solve"},
      {"Krylov Subspace Size", 200, {}, "GMRES restart length"},
      {"On Broken Direct Solver", std::string("reroute"), {"reroute", "refuse"},
       "Amesos2 direct solvers are wrong on 2+ ranks on this platform: reroute to GMRES + "
       "Schwarz/KLU2 (with a notice) or refuse (throw)"},
      {"Max Newton Iterations", 20, {}, "Maximum Newton iterations per (sub)step"},
      {"Residual Tolerance", 1e-8, {}, "Convergence: max |f| below this (and the update test)"},
      {"Update Relative Tolerance", 1e-8, {}, "Convergence: WRMS update test rtol"},
      {"Update Absolute Tolerance", 1e-10, {}, "Convergence: WRMS update test atol"},
      {"Line Search", std::string("Full Step"), {"Full Step", "Backtrack", "Polynomial", "More'-Thuente"},
       "NOX line search method"},
      {"Update Test", std::string("auto"), {"auto", "Last Update"},
       "Newton's update test of a rod time step: auto = with the block-tridiagonal LU, a step also "
       "converges when the next update, solved with the last factorisation, passes the WRMS test "
       "(then taken; no iteration whose only purpose is the update test); NOX's test with the "
       "other linear solvers; Last Update = NOX's test (the update just taken) everywhere"},
      {"Initial Guess", std::string("auto"), {"auto", "Old Level", "Secant"},
       "Newton's initial guess of a rod time step: Old Level = the old level's unknowns; Secant = "
       "the old level extrapolated along the last step's secant, y + dt (y - y_prev) / dt_prev "
       "(zero slope at a start): fewer iterations where the motion is smooth, but it can fail "
       "where the old level does not; auto = the old level extrapolated only in the entries whose "
       "change in the last step the secant before it predicted to within half, and where Newton "
       "fails from there, the old level before the step is halved (docs/solver.md)"},
      {"Max Subdivision Depth", 4, {}, "How often a failing step may be halved (0: no retry)"},
      {"Verbose", true, {}, "One-line notices on rank 0"},
      {"Jacobian Reuse", false, {},
       "Modified Newton: keep W, its factorisation or preconditioner across Newton iterations "
       "and time steps while max|f| contracts by at least 'Jacobian Reuse Contraction' per "
       "iteration; a solve that fails with a kept W is redone with full Newton"},
      {"Jacobian Reuse Contraction", 0.25, {},
       "Refresh the kept W when max|f_k| > this * max|f_{k-1}| (0 < value < 1)"},
      {"Direct Solver Path", std::string("Reuse Symbolic"), {"Reuse Symbolic", "Stratimikos"},
       "How KLU2 runs on 1 rank: Reuse Symbolic (one Amesos2 solver kept by traverse: ordering "
       "once, numeric refactorisation per new W) or Stratimikos (its Amesos2 adapter, which "
       "redoes the symbolic factorisation every time)"},
  };
  return keys;
}

namespace {

// The sublists handed to the Trilinos packages unvalidated.
const char* const kPassThrough[] = {"Stratimikos", "NOX"};

[[noreturn]] void refuse(const std::string& what) { throw std::invalid_argument("rod solver parameters: " + what); }

std::string words_text(const std::vector<std::string>& words) {
  std::string t;
  for (const auto& w : words) t += (t.empty() ? "'" : ", '") + w + "'";
  return "{" + t + "}";
}

// The type of a value or sublist as the messages name it.
std::string type_name(const Teuchos::ParameterEntry& e) {
  if (e.isList()) return "sublist";
  if (e.isType<bool>()) return "bool";
  if (e.isType<int>()) return "int";
  if (e.isType<double>()) return "double";
  if (e.isType<std::string>()) return "string";
  if (e.isType<Teuchos::Array<double>>()) return "list of numbers";
  if (e.isType<Teuchos::Array<std::string>>()) return "list of words";
  return e.getAny(false).typeName();
}

// The type of a key's default (SolverKey::default_value) by the same names.
const char* type_name(std::size_t index) {
  static const char* const names[] = {"bool", "int", "double", "string"};
  return names[index];
}

// "a " or "an " before `noun`.
std::string with_article(const std::string& noun) {
  return (!noun.empty() && std::string("aeiou").find(noun[0]) != std::string::npos ? "an " : "a ") + noun;
}

std::string known_keys() {
  std::vector<std::string> names;
  for (const auto& k : solver_keys()) names.push_back(k.name);
  for (const char* n : kPassThrough) names.emplace_back(n);
  return words_text(names);
}

}  // namespace

Teuchos::ParameterList validated_solver_parameters(const Teuchos::ParameterList& given) {
  Teuchos::ParameterList p = given;
  for (const auto& kv : given) {
    const std::string& name = kv.first;
    const Teuchos::ParameterEntry& e = kv.second;
    const auto pass = std::find(std::begin(kPassThrough), std::end(kPassThrough), name) != std::end(kPassThrough);
    if (pass) {
      if (!e.isList()) refuse("'" + name + "' must be a sublist (handed to Trilinos), found " + with_article(type_name(e)));
      continue;
    }
    const auto& keys = solver_keys();
    const auto k = std::find_if(keys.begin(), keys.end(), [&](const SolverKey& s) { return s.name == name; });
    if (k == keys.end()) refuse("unknown key '" + name + "', expected one of " + known_keys());
    const bool same_type = std::visit(
        [&](const auto& d) { return !e.isList() && e.isType<std::decay_t<decltype(d)>>(); }, k->default_value);
    if (!same_type) {
      const bool widen = std::holds_alternative<double>(k->default_value) && !e.isList() && e.isType<int>();
      if (!widen)
        refuse("'" + name + "' must be " + with_article(type_name(k->default_value.index())) + ", found " +
               with_article(type_name(e)));
      p.set(name, static_cast<double>(e.getValue<int>(nullptr)));
    }
    if (!k->words.empty()) {
      const std::string& w = p.get<std::string>(name);
      if (std::find(k->words.begin(), k->words.end(), w) == k->words.end())
        refuse("'" + name + "' must be one of " + words_text(k->words) + ", found '" + w + "'");
    }
  }
  for (const auto& k : solver_keys())
    if (!p.isParameter(k.name)) std::visit([&](const auto& v) { p.set(k.name, v); }, k.default_value);
  for (const char* n : kPassThrough) p.sublist(n);
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

Teuchos::ParameterList checked_solver_parameters(const Teuchos::ParameterList& given) {
  Teuchos::ParameterList p = validated_solver_parameters(given);
  if (given.isSublist("Stratimikos") && given.sublist("Stratimikos").numParams() > 0) {
    try {
      check_stratimikos_list(given.sublist("Stratimikos"));
    } catch (const std::invalid_argument& x) {
      refuse("'Stratimikos': " + std::string(x.what()));
    }
  }
  return p;
}

rod::InitialGuess initial_guess_of(const Teuchos::ParameterList& validated) {
  const std::string& g = validated.get<std::string>("Initial Guess");
  if (g == "Secant") return rod::InitialGuess::secant;
  return g == "Old Level" ? rod::InitialGuess::old_level : rod::InitialGuess::blend;
}

}  // namespace traverse::solver
