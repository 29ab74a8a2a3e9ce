#pragma once
// The rod with a coupled mass as the time integrator's model (docs/rod.md "Coupled mass"):
// each step a partitioned solve of rod and mass (rod::CoupledRodStepper over the distributed
// stepper), then the centreline, the contact and the events of the step (the mass leaves the
// rod, lifts off or sticks: the run ends). Adaptive attempts are checked by the rod's and the
// mass's error estimates, the larger deciding.
#include <limits>
#include <string>
#include <vector>

#include "traverse/rod/coupled_mass_rod.hpp"
#include "traverse/solver/rod_error_estimate.hpp"
#include "traverse/time/time_integrator.hpp"

namespace traverse::solver {

/// An event that ends a coupled run: "left_rod_at_0", "left_rod_at_L", "lift_off", "stick".
struct MassEvent {
  double time = 0.0, position = 0.0;
  std::string reason;
};

/// The contact of the last step (NaN before the first) and the lift-off indicator's last
/// value at the step's midpoint time.
struct ContactHistory {
  Vec3 normal = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  double tangential = std::numeric_limits<double>::quiet_NaN();
  double up_prev = 0.0, up_time = 0.0;
};

/// The adaptive estimate's quantities of the rod's nodes, and of the mass: its speed as the
/// rate of a position (the position group; the rest zero).
std::vector<rod::NodeLevel> rod_levels(const rod::RodState& s);
std::vector<rod::NodeLevel> mass_level(const rod::CoupledMassState& m);

class CoupledRodTimeModel : public time::SteppedModel {
 public:
  /// `state`, `m`: the whole rod and the mass (on every rank), stepped in place; `unilateral`:
  /// the contact can lift off; `rod_estimate`, `mass_estimate`: the adaptive steps' (both or
  /// neither).
  CoupledRodTimeModel(rod::CoupledRodStepper& stepper, rod::RodState& state, rod::CoupledMassState& m,
                      std::string mass_name, bool unilateral, RodErrorEstimate* rod_estimate,
                      RodErrorEstimate* mass_estimate);
  double time() const override { return state_.t; }
  void step(double h) override;
  time::Attempt attempt(double h) override;
  std::vector<double> accept() override;
  void reject() override;
  bool ended() const override { return !events.empty(); }

  std::vector<Vec3> r;  ///< the centreline, integrated in time
  ContactHistory contact;
  std::vector<MassEvent> events;
  long steps = 0, newton = 0, coupling = 0;  ///< accepted steps, iterations of the solves

 private:
  /// One coupled solve of length h from the current state; false (the state unchanged) when
  /// it fails. PlanarityLost: the state of the step's start, rethrown.
  bool solve(double h);
  std::string failure(double t, double h) const;
  /// The centreline, the contact and the events of the step from (old, m_old) to the state.
  void accepted(const rod::RodState& old, const rod::CoupledMassState& m_old, double h);
  double shorten_to_stop(const rod::RodState& old, const rod::CoupledMassState& m_old, double h);
  void step_events(const rod::RodState& old, const rod::CoupledMassState& m_old, double h);
  void back_to_start();
  void starting(const rod::RodState& s, const rod::CoupledMassState& m) {
    start_ = &s;
    m_start_ = &m;
  }
  rod::CoupledRodStepper& stepper_;
  rod::RodState& state_;
  rod::CoupledMassState& m_;
  std::string name_;
  bool unilateral_;
  RodErrorEstimate *rc_, *mc_;
  rod::CoupledStepReport last_;
  /// The attempt in hand: its start, its length, and with step doubling the middle.
  rod::RodState old_, mid_;
  std::vector<rod::NodeLevel> levels_;  ///< the rod's levels at the end of an extrapolated attempt
  rod::CoupledMassState m_old_, m_mid_;
  /// The start of the solve in hand (old_ or mid_): where a lost planarity returns to.
  const rod::RodState* start_ = &old_;
  const rod::CoupledMassState* m_start_ = &m_old_;
  double h_ = 0.0;
  bool doubled_ = false;
};

}  // namespace traverse::solver
