#include "traverse/setup/coupled_restart.hpp"

#include <algorithm>
#include <iterator>

namespace traverse::setup {

namespace {
const char* const kEventReasons[] = {"left_rod_at_0", "left_rod_at_L", "lift_off", "stick", "time_limit"};
}  // namespace

std::vector<double> pack_coupled_run(const solver::CoupledRodTimeModel& model, const rod::CoupledMassState& m, double dt,
                                     bool planar, double written_t) {
  namespace e = coupled_extra;
  std::vector<double> x(e::fixed, 0.0);
  const solver::ContactHistory& c = model.contact;
  x[e::dt] = dt;
  x[e::planar] = planar ? 1.0 : 0.0;
  x[e::sigma] = m.sigma;
  x[e::speed] = m.speed;
  x[e::drive_work] = m.drive_work;
  x[e::dissipated] = m.dissipated;
  x[e::friction_work] = m.friction_work;
  x[e::stick] = m.stick_fraction;
  const auto body = m.suspension_values();
  std::copy(body.begin(), body.end(), x.begin() + e::body);
  x[e::up_prev] = c.up_prev;
  x[e::up_time] = c.up_time;
  for (int k = 0; k < 3; ++k) x[e::normal + static_cast<std::size_t>(k)] = c.normal(k);
  x[e::tangential] = c.tangential;
  x[e::steps] = double(model.steps);
  x[e::newton] = double(model.newton);
  x[e::coupling] = double(model.coupling);
  x[e::written_t] = written_t;
  x[e::event_count] = double(model.events.size());
  if (!model.events.empty()) {
    const solver::MassEvent& ev = model.events[0];
    x[e::event_time] = ev.time;
    x[e::event_position] = ev.position;
    const auto* r = std::find(std::begin(kEventReasons), std::end(kEventReasons), ev.reason);
    x[e::event_reason] = double(r - std::begin(kEventReasons));
  }
  return x;
}

double unpack_coupled_run(const std::vector<double>& x, solver::CoupledRodTimeModel& model, rod::CoupledMassState& m) {
  namespace e = coupled_extra;
  m.sigma = x[e::sigma];
  m.speed = x[e::speed];
  m.drive_work = x[e::drive_work];
  m.dissipated = x[e::dissipated];
  m.friction_work = x[e::friction_work];
  m.stick_fraction = x[e::stick];
  m.set_suspension_values(&x[e::body]);
  solver::ContactHistory& c = model.contact;
  c.up_prev = x[e::up_prev];
  c.up_time = x[e::up_time];
  c.normal = Vec3(x[e::normal], x[e::normal + 1], x[e::normal + 2]);
  c.tangential = x[e::tangential];
  model.steps = static_cast<long>(x[e::steps]);
  model.newton = static_cast<long>(x[e::newton]);
  model.coupling = static_cast<long>(x[e::coupling]);
  model.events.clear();
  if (x[e::event_count] > 0.0)
    model.events.push_back(
        {x[e::event_time], x[e::event_position], kEventReasons[static_cast<std::size_t>(x[e::event_reason])]});
  return x[e::written_t];
}

}  // namespace traverse::setup
