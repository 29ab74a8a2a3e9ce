#pragma once
// Statics and continuation of the rod (docs/statics.md) on the distributed static model
// (StaticRodModel, a Thyra model evaluator with parameters) through LOCA::Thyra::Group and
// LOCA::Stepper (natural or pseudo-arclength continuation with adaptive steps; every converged
// step also has to pass an eigenvalue-change test, see ContinuationOptions::eigenvalue_change),
// with
//  - stability of every computed state: the eigenvalues omega^2 of K_s phi = omega^2 M_s phi
//    nearest zero (Anasazi Block Krylov-Schur, shift-and-invert), K_s the static Jacobian and
//    M_s the small-vibration inertia (rod::static_mass_block); unstable modes = omega^2 < 0;
//  - detection of folds and pitchforks (the unstable-mode count changes between two points:
//    a fold when the null vector lies along the branch, a pitchfork when it is orthogonal to
//    it) and their location by a bordered Newton on the hyperplanes across the chord of the
//    bracketing points with an Illinois/secant iteration on the crossing eigenvalue;
//  - branch switching at a pitchfork (perturb along the null vector, solve with the
//    amplitude fixed and the parameter free, continue from there).
// Everything here is plain data except the communicator and the solver parameters (a
// Teuchos::ParameterList); LOCA, Anasazi, NOX and Stratimikos stay inside
// src/solver/static_*.cpp. Nodes are always the full rod (gathered on every rank).
#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "traverse/rod/static_problem.hpp"

namespace traverse::solver {

/// Small-vibration analysis of a static state.
struct StabilityOptions {
  bool enabled = true;
  int num_eigenvalues = 6;  ///< omega^2 nearest the shift that are computed
  /// Shift sigma of (K_s - sigma M_s)^-1 M_s [1/s^2]; NaN: -0.01 EI / (rhoA L^4).
  double shift = std::numeric_limits<double>::quiet_NaN();
  double tolerance = 1e-10;  ///< Anasazi relative residual
};

struct Stability {
  bool converged = false;
  int unstable_modes = 0;            ///< eigenvalues with omega^2 < 0 among those computed
  std::vector<double> eigenvalues;   ///< real parts of omega^2 [1/s^2], ascending
  std::vector<double> imaginary;     ///< their imaginary parts (0 for a conservative state)
  /// The computed eigenvalue closest to zero (the bifurcation test function) [1/s^2].
  double critical = std::numeric_limits<double>::quiet_NaN();
  std::vector<Vec12> critical_mode;  ///< its eigenvector per node (real part), max |r| = 1
  int factorisations = 0;  ///< set-ups of the linear solver for K_s - s M_s in this solve (1)
  int solves = 0;          ///< solves with it (one per Krylov-Schur operator application)
  /// The linear solver of K_s - s M_s: a direct one (KLU2, else the block-tridiagonal LU), the
  /// statics' Krylov solver only where the direct one failed.
  std::string linear_solver;
};

/// One accepted continuation point.
struct ContinuationPoint {
  int step = 0;
  double parameter = 0.0;             ///< value of the continued parameter
  std::vector<double> probes;         ///< ContinuationOptions::probes, in order
  int unstable_modes = -1;            ///< -1 when stability is off or did not converge
  double critical_eigenvalue = std::numeric_limits<double>::quiet_NaN();  ///< [1/s^2]
  std::vector<rod::StaticNode> state;  ///< all nodes, frames rebased (theta = 0)
};

enum class BifurcationType { fold, pitchfork };
std::string to_string(BifurcationType t);  ///< "fold", "pitchfork"

struct Bifurcation {
  BifurcationType type = BifurcationType::fold;
  double parameter = 0.0;           ///< located parameter value
  std::vector<double> probes;       ///< probes at the located state
  std::vector<rod::StaticNode> state;
  std::vector<Vec12> null_vector;   ///< per node, max |r| = 1
  int unstable_before = 0, unstable_after = 0;  ///< counts at the bracketing points
  int after_point = 0;              ///< index of the first point past it in ContinuationResult::points
  bool located = false;             ///< false: only bracketed (location did not converge)
  double test_function = std::numeric_limits<double>::quiet_NaN();  ///< eigenvalue at the located state
  int locate_iterations = 0;
};

struct ContinuationOptions {
  rod::StaticParameter parameter = rod::StaticParameter::end_load;
  std::string method = "Arc Length";  ///< LOCA "Continuation Method": "Arc Length" or "Natural"
  /// Bounds of the parameter: the run stops at the first point outside them (or closer to the
  /// bound it heads for than 1e-3 max_step) and, when land_on_bounds, replaces that point by
  /// the solution on the bound (a fixed-parameter solve) before it is recorded.
  double min_value = -std::numeric_limits<double>::infinity();
  double max_value = std::numeric_limits<double>::infinity();
  bool land_on_bounds = true;
  double initial_step = 0.01;  ///< signed: its sign sets the initial direction of the parameter
  double min_step = 1e-7, max_step = 0.1;
  double step_aggressiveness = 0.5;  ///< LOCA adaptive step size
  int max_steps = 200;
  int max_newton_iterations = 12;
  double residual_tolerance = 1e-9;   ///< Newton: max-norm of the residual ...
  double update_tolerance = 1e-10;    ///< ... and WRMS norm of the update (rtol = atol)
  std::vector<rod::StaticProbe> probes;
  StabilityOptions stability;
  bool detect_bifurcations = true;    ///< needs stability
  bool locate_bifurcations = true;
  double locate_tolerance = 1e-11;    ///< step of the chord coordinate c (0..1) that ends the location
  /// Step acceptance (needs stability): a converged step is rejected, and retried with half
  /// the step, when one of the eigenvalues omega^2 up to the one that crosses zero changes by
  /// more than eigenvalue_change * max(|its value|, floor), floor = eigenvalue_floor times
  /// the largest |lowest omega^2| seen on the run (at least 10 EI/(rhoA L^4)). So the steps
  /// shrink where an eigenvalue heads for zero (a fold or a pitchfork ahead), a step that jumps
  /// past a fold onto a state with different eigenvalues is retried, and the bracket of a
  /// crossing is small. 0: off.
  double eigenvalue_change = 0.5;
  double eigenvalue_floor = 0.05;
  /// Called after each point is recorded; return true to stop the run after it.
  std::function<bool(const ContinuationPoint&)> stop;
  /// Linear solver keys of solver_parameters.hpp ("Linear Solver", ...; KLU2 is rerouted
  /// on 2+ ranks); empty: defaults.
  Teuchos::ParameterList solver;
  bool verbose = false;  ///< LOCA stepper output on rank 0
};

struct ContinuationResult {
  std::string parameter;               ///< parameter_name(options.parameter)
  std::string parameter_unit;
  std::vector<std::string> probe_names, probe_units;
  std::vector<ContinuationPoint> points;
  std::vector<Bifurcation> bifurcations;
  bool completed = false;   ///< reached a bound, the stop callback or max_steps without failure
  int rejected_steps = 0;   ///< converged steps rejected by the acceptance tests (and retried smaller)
  std::string message;      ///< how it ended
  rod::StaticProblem final_problem;  ///< the problem with the parameter of the last point
};

using PointCallback = std::function<void(const ContinuationPoint&)>;
using Comm = Teuchos::RCP<const Teuchos::Comm<int>>;

/// Continuation of `problem` (its values give the start, including the continued parameter)
/// from `start`, an equilibrium or a good guess (solved first). Collective over `comm`.
ContinuationResult continue_(const rod::StaticProblem& problem, const std::vector<rod::StaticNode>& start,
                             const ContinuationOptions& options, const Comm& comm,
                             const PointCallback& on_point = {});

/// Newton at fixed parameters from `state` (in place: the solution with rebased frames).
struct StaticSolveReport {
  bool converged = false;
  int iterations = 0;
  double residual_norm = 0.0;  ///< max |f|
  std::string message;
};
StaticSolveReport static_solve(const rod::StaticProblem& problem, std::vector<rod::StaticNode>& state,
                               const Comm& comm, const Teuchos::ParameterList& solver = {});

/// Small-vibration eigenvalues about an equilibrium `state` of `problem`.
Stability static_stability(const rod::StaticProblem& problem, const std::vector<rod::StaticNode>& state,
                           const Comm& comm, const StabilityOptions& options = {},
                           const Teuchos::ParameterList& solver = {});

/// Branch switching at a pitchfork found by a run of `options.parameter` on `problem`:
/// the bifurcation state perturbed by `amplitude` times its null vector (sign included; the
/// null vector has max |r| = 1, so amplitude is a displacement [m]), solved with that
/// amplitude fixed and the parameter free, then continued with `options` (the initial
/// direction chosen so the amplitude grows; the sign of options.initial_step is ignored).
ContinuationResult switch_branch(const rod::StaticProblem& problem, const Bifurcation& pitchfork,
                                 double amplitude, const ContinuationOptions& options, const Comm& comm,
                                 const PointCallback& on_point = {});

/// Nodes of `a` minus nodes of `b` in the same frames (a helper for probes and tests).
double max_position_difference(const std::vector<rod::StaticNode>& a, const std::vector<rod::StaticNode>& b);

/// The peak memory of a continuation (and of the arch formation, which is one) per owned node
/// [bytes]: LOCA's extended vectors and predictors, the Newton system, Anasazi's basis for up to
/// 6 eigenvalues (measured as time_step_bytes_per_node is).
double continuation_bytes_per_node();

}  // namespace traverse::solver
