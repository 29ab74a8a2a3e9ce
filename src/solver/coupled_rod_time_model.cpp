#include "traverse/solver/coupled_rod_time_model.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "traverse/solver/rod_stepper.hpp"

namespace traverse::solver {

std::vector<rod::NodeLevel> rod_levels(const rod::RodState& s) {
  std::vector<rod::NodeLevel> y;
  y.reserve(s.nodes.size());
  for (const auto& nd : s.nodes) y.push_back(rod::node_level(nd));
  return y;
}

std::vector<rod::NodeLevel> mass_level(const rod::CoupledMassState& m) {
  rod::NodeLevel y = rod::NodeLevel::Zero();
  y(0) = m.speed;
  return {y};
}

CoupledRodTimeModel::CoupledRodTimeModel(rod::CoupledRodStepper& stepper, rod::RodState& state,
                                         rod::CoupledMassState& m, std::string mass_name, bool unilateral,
                                         RodErrorEstimate* rod_estimate, RodErrorEstimate* mass_estimate)
    : r(rod::centreline_in_space(state)), stepper_(stepper), state_(state), m_(m), name_(std::move(mass_name)),
      unilateral_(unilateral), rc_(rod_estimate), mc_(mass_estimate) {}

bool CoupledRodTimeModel::solve(double h) {
  rod::CoupledStepReport rep;
  try {
    rep = stepper_.step(state_, m_, h);
  } catch (const PlanarityLost&) {
    state_ = *start_;
    m_ = *m_start_;
    throw;
  }
  newton += rep.newton_iterations;
  coupling += rep.coupling_iterations;
  last_ = rep;
  return rep.converged;
}

std::string CoupledRodTimeModel::failure(double t, double h) const {
  std::ostringstream os;
  os.precision(9);
  os << "the coupled step of rod and mass '" << name_ << "' from t = " << t << " s over dt = " << h
     << " s did not converge (" << last_.coupling_iterations << " coupling iterations, last change "
     << last_.last_change << " ds)";
  return os.str();
}

void CoupledRodTimeModel::back_to_start() {
  state_ = old_;
  m_ = m_old_;
}

void CoupledRodTimeModel::step(double h) {
  old_ = state_;
  m_old_ = m_;
  starting(old_, m_old_);
  if (!solve(h)) throw time::StepFailed(failure(old_.t, h) + "; reduce time.dt");
  accepted(old_, m_old_, h);
}

// A step in which the friction stopped the mass (rod::CoupledMassState::stick_fraction): redone
// from (old, m_old) with the step shortened to the stop (secant on the length for sigma' = 0,
// from the linear zero of the step); the state at the stop and its length (0: stuck at the start).
double CoupledRodTimeModel::shorten_to_stop(const rod::RodState& old, const rod::CoupledMassState& m_old, double h) {
  double ha = h, va = m_.speed, hb = m_.stick_fraction * h;
  for (int it = 0; it < 8 && hb > 0.0; ++it) {
    state_ = old;
    m_ = m_old;
    if (!solve(hb)) {
      --steps;
      throw time::StepFailed(failure(old.t, hb) + " (the step shortened to the mass's stop)");
    }
    const double vb = m_.speed;
    if (std::abs(vb) <= 1e-12 * std::abs(m_old.speed) || vb == va) break;
    const double next = std::clamp(hb - vb * (hb - ha) / (vb - va), 0.0, h);
    ha = hb;
    va = vb;
    hb = next;
  }
  if (hb <= 0.0) {
    state_ = old;
    m_ = m_old;
    return 0.0;
  }
  return hb;
}

void CoupledRodTimeModel::accepted(const rod::RodState& old, const rod::CoupledMassState& m_old, double h) {
  starting(old, m_old);  // a shortened step starts here too
  ++steps;
  const bool stuck = m_.sticks();
  if (stuck) h = shorten_to_stop(old, m_old, h);
  if (h > 0.0) step_events(old, m_old, h);
  if (stuck && events.empty()) events.push_back({state_.t, m_.sigma, "stick"});
}

// The centreline, the contact and the events (leaving, lift-off) of a step of length h > 0.
void CoupledRodTimeModel::step_events(const rod::RodState& old, const rod::CoupledMassState& m_old, double h) {
  r = rod::advance_centreline_in_time(r, old, state_);
  const rod::CoupledContact c =
      rod::step_contact(old, m_old, state_, m_, stepper_.coupled_mass(), stepper_.model(), h);
  const double L = stepper_.model().length;
  if (m_.sigma < 0.0 || m_.sigma > L) {  // left the rod in this step: the time where sigma crosses the end
    const double edge = m_.sigma < 0.0 ? 0.0 : L;
    const double te = old.t + h * (edge - m_old.sigma) / (m_.sigma - m_old.sigma);
    events.push_back({te, edge, edge == 0.0 ? "left_rod_at_0" : "left_rod_at_L"});
  } else if (unilateral_ && c.up < 0.0) {
    // lift-off: the zero of C . d2 between the steps' midpoints
    const double tm = old.t + 0.5 * h;
    const double t0 = steps > 1 ? contact.up_time : tm;
    const double f = steps > 1 && contact.up_prev > 0.0 ? contact.up_prev / (contact.up_prev - c.up) : 1.0;
    const double te = t0 + f * (tm - t0);
    const double se = te <= old.t ? m_old.sigma : m_old.sigma + (te - old.t) / h * (m_.sigma - m_old.sigma);
    events.push_back({te, se, "lift_off"});
  }
  contact.up_prev = c.up;
  contact.up_time = old.t + 0.5 * h;
  contact.normal = c.normal;
  contact.tangential = c.tangential;
}

// One step of h checked by the estimates (step doubling while the history is short).
time::Attempt CoupledRodTimeModel::attempt(double h) {
  time::Attempt a;
  old_ = state_;
  m_old_ = m_;
  starting(old_, m_old_);
  h_ = h;
  doubled_ = !rc_->has_history();
  auto failed = [&](double t, double length) {
    a.why = failure(t, length);
    back_to_start();
    return a;
  };
  if (!solve(h)) return failed(old_.t, h);
  if (doubled_) {
    const auto full = rod_levels(state_), full_m = mass_level(m_);
    back_to_start();
    if (!solve(0.5 * h)) return failed(old_.t, 0.5 * h);
    mid_ = state_;
    m_mid_ = m_;
    if (!solve(0.5 * h)) return failed(mid_.t, 0.5 * h);
    a.error = std::max(rc_->doubling_error(full, rod_levels(mid_), rod_levels(state_), h),
                       mc_->doubling_error(full_m, mass_level(m_mid_), mass_level(m_), h));
  } else {
    levels_ = rod_levels(state_);  // kept for accept() unless a stop shortens the step
    a.error = std::max(rc_->extrapolation_error(levels_, h), mc_->extrapolation_error(mass_level(m_), h));
  }
  a.converged = true;
  // The Newton signal: iterations per rod solve (the step makes one per coupling iteration).
  a.newton = last_.newton_iterations / std::max(1, last_.coupling_iterations);
  return a;
}

std::vector<double> CoupledRodTimeModel::accept() {
  if (!doubled_) {
    const bool shortened = m_.sticks();  // accepted() then redoes the step to the stop
    accepted(old_, m_old_, h_);
    rc_->accept(shortened ? rod_levels(state_) : std::move(levels_), h_);
    mc_->accept(mass_level(m_), h_);
    return {h_};
  }
  std::vector<double> lengths;
  const rod::RodState end = state_;
  const rod::CoupledMassState m_end = m_;
  for (int part = 0; part < 2 && events.empty(); ++part) {  // the two half steps, in order
    state_ = part == 0 ? mid_ : end;
    m_ = part == 0 ? m_mid_ : m_end;
    accepted(part == 0 ? old_ : mid_, part == 0 ? m_old_ : m_mid_, 0.5 * h_);
    rc_->accept(rod_levels(state_), 0.5 * h_);
    mc_->accept(mass_level(m_), 0.5 * h_);
    lengths.push_back(0.5 * h_);
  }
  return lengths;
}

void CoupledRodTimeModel::reject() { back_to_start(); }

}  // namespace traverse::solver
