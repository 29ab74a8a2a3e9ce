#pragma once
// Plain description of a beam + moving-load simulation (filled in by the scene glue).
#include <memory>
#include <vector>

#include "traverse/core/step_controller.hpp"
#include "traverse/time/time_integrator.hpp"
#include "traverse/beam/galerkin.hpp"
#include "traverse/beam/modal_damping.hpp"
#include "traverse/beam/mode_set.hpp"
#include "traverse/beam/moving_load.hpp"
#include "traverse/beam/uniform_modes.hpp"

namespace traverse::beam {

enum class Integrator {
  RK4,     ///< classical 4th-order Runge-Kutta on (Y, Y') (explicit; the reference method)
  Newmark  ///< average-acceleration Newmark = trapezoidal rule (implicit, order 2, A-stable)
};

enum class InitialState {
  Static,  ///< Kb Y = -Pb + sum F_k Phi(x_k) over loads on the beam at t_start, Y' = 0
  Rest     ///< Y = 0, Y' = 0 (undeflected beam at rest)
};

/// Everything a BeamSimulation needs. SI units.
struct BeamProblem {
  // --- beam ---
  double length = 1.0;  ///< L [m]
  double EI = 1.0;      ///< bending stiffness [N m^2] (uniform value; also used for the modes)
  double rhoA = 1.0;    ///< mass per unit length [kg/m] (uniform value; also used for the modes)
  SectionFunction EI_of_x;    ///< optional EI(x) for the Galerkin integrals (default: EI)
  SectionFunction rhoA_of_x;  ///< optional rhoA(x) for the Galerkin integrals (default: rhoA)
  Support support = Support::SimplySupported;
  int n_modes = 3;
  /// Optional externally built mode set (e.g. numerically computed tapered-beam modes);
  /// when set it replaces UniformModes(support, n_modes, length, EI, rhoA).
  std::shared_ptr<const ModeSet> modes;
  /// Quadrature node set 0 = x_0 < ... < x_N = L; empty: uniform with max(16, 4 n) elements.
  std::vector<double> quadrature_nodes;
  int gauss_points = 8;  ///< Gauss-Legendre points per element
  /// Structural damping in the beam's modes (none by default): the modal equations gain C Y'.
  ModalDamping damping;

  // --- loading ---
  double gravity = 9.8;     ///< g [m/s^2], acts along -w
  bool self_weight = true;  ///< include the beam's own weight (-Pb)
  std::vector<MovingLoad> loads;
  InitialState initial_state = InitialState::Static;

  // --- time integration ---
  double t_start = 0.0;  ///< [s]
  double t_end = 1.0;    ///< [s], reached exactly (the last step is shortened)
  double dt = 1e-3;      ///< nominal fixed step [s]
  Integrator integrator = Integrator::RK4;
  int output_every = 1;  ///< observer every k grid steps (plus initial and final states)
  /// Evaluate the modal accelerations Y'' at the output instants (BeamSnapshot::acceleration):
  /// one more solve of the equation of motion per output.
  bool accelerations = false;
  /// Split a step at the instants where a load enters or leaves the beam, so that the
  /// piecewise-smooth right-hand side keeps the methods' full order.
  bool split_at_load_events = true;
  /// Adaptive steps (time.adaptive, docs/adaptive.md): dt is the first step; the steps land on
  /// the grid times of dt (the output times) and on the load events. Step doubling estimates
  /// each step's error (order 4 for RK4, 2 for Newmark); `adaptive.order` is set from the
  /// integrator.
  bool adaptive = false;
  StepControlParameters control;
};

/// Circular tube: returns {EI [N m^2], rhoA [kg/m]} for E [Pa], rho [kg/m^3], radii [m].
struct Section {
  double EI;
  double rhoA;
};
Section circular_tube(double E, double rho, double r_outer, double r_inner);

/// The steps of a run of `p` (time/time_integrator.hpp): the grid of dt from t_start to t_end
/// (a remainder below 1e-9 dt joins the last step instead of making a sliver step), an output
/// every output_every steps, adaptive with p.adaptive; `split_at_kinks`: fixed steps end where
/// a load enters or leaves the beam.
time::Schedule beam_schedule(const BeamProblem& p, bool split_at_kinks);

}  // namespace traverse::beam
