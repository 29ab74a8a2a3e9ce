#pragma once
// The values a coupled rod run's restart point keeps beside its nodes (docs/reliability.md
// "Restart"): the fixed part below (the time step and path, the mass's state with its
// suspension, the contact history, the counters, the event), then with time.adaptive the
// estimates' values, which the run appends.
#include <cstddef>
#include <vector>

#include "traverse/rod/coupled_mass_rod.hpp"
#include "traverse/solver/coupled_rod_time_model.hpp"

namespace traverse::setup {

namespace coupled_extra {
/// Positions in the fixed part (body: a suspension's z, z', w, w', force, damper work).
enum : std::size_t {
  dt, planar, sigma, speed, drive_work, dissipated, friction_work, stick, up_prev, up_time, normal,
  tangential = normal + 3, steps, newton, coupling, written_t, event_count, event_time, event_position, event_reason,
  body, fixed = body + 6
};
}  // namespace coupled_extra

/// The fixed part of the values of `model` (its contact history, counters and first event) and
/// of the mass `m`, with the time step `dt`, the path and the time last written.
std::vector<double> pack_coupled_run(const solver::CoupledRodTimeModel& model, const rod::CoupledMassState& m, double dt,
                                     bool planar, double written_t);

/// Restores what pack_coupled_run packed (the first coupled_extra::fixed values of `x`) into
/// `model` and `m`; returns the time last written.
double unpack_coupled_run(const std::vector<double>& x, solver::CoupledRodTimeModel& model, rod::CoupledMassState& m);

}  // namespace traverse::setup
