// A rod run with a coupled mass (docs/rod.md "Coupled mass"): the mass's position an
// unknown of each step (rod::CoupledRodStepper), the rod's step solved by
// solver::RodStepper (any ranks, the planar or the 3D path, any linear solver), the whole
// state kept on every rank between the steps. Outputs: the rod's probes and fields, the mass's probes (position, speed, fixed-frame position
// and velocity, contact forces), the energies, and the events table (the run ends when the mass
// leaves the rod).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "interrupt.hpp"
#include "mpi_session.hpp"
#include "restart.hpp"
#include "progress.hpp"
#include "rod_adaptive.hpp"
#include "rod_quantities.hpp"
#include "rod_setup.hpp"
#include "run.hpp"
#include "run_beam_coupled.hpp"
#include "run_rod_coupled.hpp"
#include "traverse/output/restart.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/rod/coupled_mass_rod.hpp"
#include "traverse/solver/coupled_rod_solve.hpp"
#include "traverse/version.hpp"

namespace traverse::app {

namespace {

constexpr int kMaxCoupledNodes = 20001;  // the whole state is kept (and gathered each step) on every rank

}  // namespace

void check_coupled_rod(const scene::Scene& sc, const rod::RodModel& model) {
  const auto& a = model.alpha;
  for (double w : {a.as, a.bs, a.gs, a.at, a.bt, a.gt})
    if (w != 0.5)
      scene::fail_at(sc, "scheme.rho_inf", "rho_inf = rho_inf_space = 1 (all six parameters 1/2) with a coupled_mass "
                     "(its midpoint rule is the box scheme's; other parameters are not yet supported)",
                     "parameters (" + scene::format_number(a.as) + ", " + scene::format_number(a.bs) + ", " +
                         scene::format_number(a.gs) + ", " + scene::format_number(a.at) + ", " +
                         scene::format_number(a.bt) + ", " + scene::format_number(a.gt) + ")");
  if (sc.mesh.nodes > kMaxCoupledNodes)
    scene::fail_at(sc, sc.has("mesh.ds") ? "mesh.ds" : "mesh.nodes",
                   "at most " + std::to_string(kMaxCoupledNodes) + " nodes with a coupled_mass on the rod (its run "
                   "keeps the whole rod on every rank)", std::to_string(sc.mesh.nodes) + " nodes");
}

namespace {

/// The contact of the last step (NaN before the first).
struct StepContact {
  Vec3 normal = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  double tangential = std::numeric_limits<double>::quiet_NaN();
};

class CoupledRodOutputs {
 public:
  /// The fields of nodes first .. first + count - 1 are this rank's.
  CoupledRodOutputs(const scene::Scene& sc, const scene::MovingLoadSpec& load, const rod::RodModel& model, int first,
                    int count)
      : sc_(sc), load_(load), model_(model), first_(first), count_(count) {}
  output::NodeLayout layout() const {
    output::NodeLayout l;
    l.global_count = static_cast<size_t>(sc_.mesh.nodes);
    l.first = static_cast<size_t>(first_);
    l.count = static_cast<size_t>(count_);
    for (int j = first_; j < first_ + count_; ++j) l.s.push_back(j * sc_.mesh.ds);
    return l;
  }
  void declare(output::Writer& w) const;
  std::vector<std::string> probe_names() const;
  std::vector<std::string> field_names() const;
  /// Evaluates the outputs at a state and writes them.
  void write(output::Writer& w, const rod::RodState& s, const std::vector<Vec3>& r, const rod::CoupledMassState& m,
             const StepContact& c);

 private:
  const scene::Scene& sc_;
  const scene::MovingLoadSpec& load_;
  const rod::RodModel& model_;
  int first_, count_;
  std::vector<std::vector<double>> probes_, fields_;
};

const char* const kMassProbes[] = {"_position", "_speed", "_fixed_position", "_fixed_velocity", "_normal_force",
                                    "_tangential_force"};
const char* const kEnergyProbes[] = {"energy_rod", "energy_rod_gravity", "energy_mass_kinetic", "energy_mass_gravity",
                                     "work_drive", "work_dissipated", "work_friction", "energy_balance"};

std::vector<std::string> CoupledRodOutputs::probe_names() const {
  std::vector<std::string> names;
  for (const auto& pr : sc_.output.probes) names.push_back(pr.name);
  for (const char* q : kMassProbes) names.push_back(load_.name + q);
  for (const char* e : kEnergyProbes) names.push_back(e);
  return names;
}

std::vector<std::string> CoupledRodOutputs::field_names() const {
  std::vector<std::string> names;
  for (const auto f : sc_.output.fields) names.push_back(scene::name_of(f));
  return names;
}

void CoupledRodOutputs::declare(output::Writer& w) const {
  declare_rod_probes(w, sc_.output.probes);
  const std::vector<std::string> xyz{"x", "y", "z"};
  const std::string n = load_.name, q = "coupled mass '" + n + "'";
  w.add_probe({n + "_position", 1, "m", "arclength sigma(t) of " + q, {}});
  w.add_probe({n + "_speed", 1, "m/s", "speed sigma'(t) of " + q + " along the rod (signed)", {}});
  w.add_probe({n + "_fixed_position", 3, "m", "fixed-frame position r(sigma) of " + q, xyz});
  w.add_probe({n + "_fixed_velocity", 3, "m/s", "fixed-frame velocity p' = U + sigma' d3 of " + q, xyz});
  w.add_probe({n + "_normal_force", 3, "N", "normal contact force of the rod on " + q +
               ", fixed frame, over the step ending here (NaN at t = 0)", xyz});
  w.add_probe({n + "_tangential_force", 1, "N", "tangential contact force of the rod on " + q +
               " (0 without friction; NaN at t = 0)", {}});
  const std::pair<const char*, const char*> energies[] = {
      {"energy_rod", "rod kinetic + elastic energy (discrete_energy, cell averages)"},
      {"energy_rod_gravity", "rod gravity potential, -int rhoA g . r ds"},
      {"energy_mass_kinetic", "kinetic energy of the coupled mass 1/2 M |p'|^2"},
      {"energy_mass_gravity", "gravity potential of the coupled mass -M g . r(sigma)"},
      {"work_drive", "work of the drive since the start"},
      {"work_dissipated", "work dissipated by the resistance since the start"},
      {"work_friction", "work dissipated by the Coulomb friction since the start, int mu |C_perp| |sigma'| dt"},
      {"energy_balance", "mechanical energy - work_drive + work_dissipated + work_friction (constant up to the "
                         "discretisation)"}};
  for (const auto& [name, what] : energies) w.add_probe({name, 1, "J", what, {}});
  for (const auto f : sc_.output.fields) {
    const RodFieldInfo fi = rod_field_info(f);
    w.add_field({scene::name_of(f), fi.components, fi.units, fi.description, fi.component_names, fi.geometry});
  }
}

void CoupledRodOutputs::write(output::Writer& w, const rod::RodState& s, const std::vector<Vec3>& r,
                              const rod::CoupledMassState& m, const StepContact& c) {
  probes_.clear();
  const int N = s.num_cells();
  auto view = [&](int j) { return node_view(s.nodes[static_cast<size_t>(j)], r[static_cast<size_t>(j)]); };
  for (const auto& pr : sc_.output.probes) {
    const Vec3 v = quantity_at(pr.quantity, pr.at, sc_.mesh.ds, N, model_.props, pr.frame, view);
    probes_.push_back({v.x(), v.y(), v.z()});
  }
  const rod::NodeInterpolation at = rod::locate_on_nodes(m.sigma, s.ds, N);
  const Vec3 rp = (1.0 - at.xi) * r[static_cast<size_t>(at.j)] + at.xi * r[static_cast<size_t>(at.j + 1)];
  const Vec3 pv = rod::mass_velocity(s, m);
  probes_.push_back({m.sigma});
  probes_.push_back({m.speed});
  probes_.push_back({rp.x(), rp.y(), rp.z()});
  probes_.push_back({pv.x(), pv.y(), pv.z()});
  probes_.push_back({c.normal.x(), c.normal.y(), c.normal.z()});
  probes_.push_back({c.tangential});
  const auto e = rod::coupled_energies(model_, s, r, m, load_.mass);
  for (double v : {e.rod, e.rod_gravity, e.mass_kinetic, e.mass_gravity, e.drive_work, e.dissipated, e.friction_work,
                   e.balance()})
    probes_.push_back({v});
  fields_.resize(sc_.output.fields.size());
  for (size_t f = 0; f < sc_.output.fields.size(); ++f) {
    const scene::Field field = sc_.output.fields[f];
    const size_t comps = field == scene::Field::R ? 9 : 3;
    fields_[f].resize(comps * static_cast<size_t>(count_));
    for (int j = first_; j < first_ + count_; ++j) {
      const auto& nd = s.nodes[static_cast<size_t>(j)];
      double* o = fields_[f].data() + comps * static_cast<size_t>(j - first_);
      if (field == scene::Field::R) {
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) o[3 * i + k] = nd.R(i, k);
      } else {
        const Vec3 v = quantity_value(field_quantity(field), view(j), model_.props, scene::Frame::body);
        std::copy(v.data(), v.data() + 3, o);
      }
    }
  }
  std::vector<output::DoubleView> views(fields_.begin(), fields_.end());
  w.write_step(s.t, {m.sigma}, probes_, views);
}

/// The adaptive estimate's quantities of the rod's nodes, and of the mass: its speed as the rate
/// of a position (the position group; the rest zero).
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

/// Restart points of a coupled rod run (docs/reliability.md "Restart"): per node the node
/// (rod::kPackedNodeValues values), its point of the centreline (3) and with time.adaptive the rod
/// controller's values (RodAdaptiveControl::kPerNode); `extra` holds the values below, then with
/// time.adaptive the mass controller's per-node values, the count of the rod controller's
/// scalars, those scalars and the mass controller's.
namespace extra {
enum : std::size_t {
  dt, planar, sigma, speed, drive_work, dissipated, friction_work, stick, up_prev, up_time, normal,
  tangential = normal + 3, steps, newton, coupling, written_t, event_count, event_time, event_position, event_reason,
  fixed
};
}  // namespace extra
const char* const kEventReasons[] = {"left_rod_at_0", "left_rod_at_L", "lift_off", "stick", "time_limit"};
std::size_t coupled_restart_components(bool adaptive) {
  return rod::kPackedNodeValues + 3 + (adaptive ? RodAdaptiveControl::kPerNode : 0);
}

/// The time loop of rod + coupled mass: the steps (fixed, or adaptive: time.adaptive), the
/// contact and the events after each accepted step, the output steps and interrupts.
class CoupledLoop {
 public:
  /// `first`, `count`: this rank's nodes (the restart point's share); `planar`: the path.
  CoupledLoop(const scene::Scene& sc, rod::CoupledRodStepper& stepper, rod::RodState& state, rod::CoupledMassState& m,
              CoupledRodOutputs& outputs, output::Writer& w, const RunOptions& opt, const TimeGrid& g, bool planar,
              int first, int count, MPI_Comm comm, Progress& progress);
  void write() {  // once per time (a stick at the start of a step ends the run at a time already written)
    if (state_.t == written_t_) return;
    written_t_ = state_.t;
    out_.write(w_, state_, r_, m_, contact_);
  }
  void run_fixed();
  void run_adaptive();
  /// Stores a restart point of the current state (collective).
  void store();
  /// Continues from a restart point: the state, the mass, the loop's own values.
  void restore(const output::RestartPoint& point);
  std::vector<output::RunEvent> events;
  long newton = 0, coupling = 0, steps = 0;
  std::string adaptive_summary() const { return rc_ ? rc_->totals().summary() : std::string(); }
  /// The adaptive counters, or nullptr for fixed steps.
  const StepControlTotals* adaptive_totals() const { return rc_ ? &rc_->totals() : nullptr; }

 private:
  /// One coupled solve of length h from the current state; false (state unchanged) when it fails.
  bool solve(double h) {
    rod::CoupledStepReport rep;
    try {
      rep = stepper_.step(state_, m_, h);
    } catch (const solver::PlanarityLost& e) {  // the state as at the start of the step
      state_ = *step_old_;
      m_ = *m_step_old_;
      fail(std::string(e.what()) + "; traverse run --restart " + opt_.output +
           " --set scheme.planar=off continues on the 3D path");
    }
    newton += rep.newton_iterations;
    coupling += rep.coupling_iterations;
    last_ = rep;
    return rep.converged;
  }
  /// Ends the run with a numerical failure; the state is that before the failed step (its
  /// restart point is stored).
  [[noreturn]] void fail(const std::string& why) {
    progress_.done();
    store();
    w_.fail(why + " (traverse run --restart " + opt_.output + " --set ... continues from t = " +
            scene::format_number(state_.t) + " s)");
    throw NumericsError(why);
  }
  /// A step starts from (old, m_old): the state a failure inside it returns to.
  void starting(const rod::RodState& old, const rod::CoupledMassState& m_old) {
    step_old_ = &old;
    m_step_old_ = &m_old;
  }
  std::string failure(double t, double h) const {
    std::ostringstream os;
    os.precision(9);
    os << "time step " << steps + 1 << " (t = " << t << " s, dt = " << h << " s): the coupled step of rod and mass '"
       << load_.name << "' did not converge (" << last_.coupling_iterations << " coupling iterations, last change "
       << last_.last_change << " ds)";
    return os.str();
  }
  void accepted(const rod::RodState& old, const rod::CoupledMassState& m_old, double h);
  double shorten_to_stop(const rod::RodState& old, const rod::CoupledMassState& m_old, double h);
  void step_events(const rod::RodState& old, const rod::CoupledMassState& m_old, double h);
  void check_interrupt(bool more) {
    if (const int sig = more && events.empty() ? interrupt_requested(comm_) : 0)
      stop_interrupted_run(sig, state_.t, "time step " + std::to_string(steps), w_, opt_.output, progress_,
                           [&] { store(); });
  }
  bool adaptive_step(double h);
  /// After an output step: a restart point when the interval has passed (rank 0's clock decides).
  void store_if_due() {
    if (restart_due(stored_, opt_.restart_interval, comm_)) store();
  }
  std::vector<double> restart_extra() const;
  const scene::Scene& sc_;
  const scene::MovingLoadSpec& load_;
  rod::CoupledRodStepper& stepper_;
  rod::RodState& state_;
  rod::CoupledMassState& m_;
  CoupledRodOutputs& out_;
  output::Writer& w_;
  const RunOptions& opt_;
  const TimeGrid& g_;
  bool planar_;
  int first_, count_;
  MPI_Comm comm_;
  Progress& progress_;
  std::vector<Vec3> r_;
  StepContact contact_;
  rod::CoupledStepReport last_;
  double up_prev_ = 0.0, up_time_ = 0.0;
  double written_t_ = std::numeric_limits<double>::quiet_NaN();
  const rod::RodState* step_old_ = nullptr;
  const rod::CoupledMassState* m_step_old_ = nullptr;
  /// time.adaptive: the rod's controller and the mass's (its position only).
  std::unique_ptr<RodAdaptiveControl> rc_, mc_;
  output::RestartSlots slots_;
  std::chrono::steady_clock::time_point stored_ = std::chrono::steady_clock::now();
};

CoupledLoop::CoupledLoop(const scene::Scene& sc, rod::CoupledRodStepper& stepper, rod::RodState& state,
                         rod::CoupledMassState& m, CoupledRodOutputs& outputs, output::Writer& w, const RunOptions& opt,
                         const TimeGrid& g, bool planar, int first, int count, MPI_Comm comm, Progress& progress)
    : sc_(sc), load_(*coupled_load(sc)), stepper_(stepper), state_(state), m_(m), out_(outputs), w_(w), opt_(opt),
      g_(g), planar_(planar), first_(first), count_(count), comm_(comm), progress_(progress),
      r_(rod::centreline_in_space(state)),
      slots_(comm, coupled_restart_components(sc.time.adaptive.enabled), static_cast<std::size_t>(first)) {
  if (!sc.time.adaptive.enabled) return;
  rc_ = std::make_unique<RodAdaptiveControl>(sc.time.adaptive, g.dt, stepper.model().alpha, sc.rod.length,
                                             MPI_COMM_NULL);
  scene::AdaptiveSpec mass_spec = sc.time.adaptive;  // the mass: its position only
  mass_spec.controlled = {true, false, false, false, false};
  mc_ = std::make_unique<RodAdaptiveControl>(mass_spec, g.dt, stepper.model().alpha, sc.rod.length, MPI_COMM_NULL);
  rc_->start(rod_levels(state_));
  mc_->start(mass_level(m_));
}

std::vector<double> CoupledLoop::restart_extra() const {
  std::vector<double> x(extra::fixed, 0.0);
  x[extra::dt] = g_.dt;
  x[extra::planar] = planar_ ? 1.0 : 0.0;
  x[extra::sigma] = m_.sigma;
  x[extra::speed] = m_.speed;
  x[extra::drive_work] = m_.drive_work;
  x[extra::dissipated] = m_.dissipated;
  x[extra::friction_work] = m_.friction_work;
  x[extra::stick] = m_.stick_fraction;
  x[extra::up_prev] = up_prev_;
  x[extra::up_time] = up_time_;
  for (int c = 0; c < 3; ++c) x[extra::normal + c] = contact_.normal(c);
  x[extra::tangential] = contact_.tangential;
  x[extra::steps] = double(steps);
  x[extra::newton] = double(newton);
  x[extra::coupling] = double(coupling);
  x[extra::written_t] = written_t_;
  x[extra::event_count] = double(events.size());
  if (!events.empty()) {
    x[extra::event_time] = events[0].time;
    x[extra::event_position] = events[0].position;
    const auto* r = std::find(std::begin(kEventReasons), std::end(kEventReasons), events[0].reason);
    x[extra::event_reason] = double(r - std::begin(kEventReasons));
  }
  if (rc_) {
    std::vector<double> mass_node(RodAdaptiveControl::kPerNode);
    mc_->pack_node(0, mass_node.data());
    const std::vector<double> a = rc_->pack_scalars(), b = mc_->pack_scalars();
    x.insert(x.end(), mass_node.begin(), mass_node.end());
    x.push_back(double(a.size()));
    x.insert(x.end(), a.begin(), a.end());
    x.insert(x.end(), b.begin(), b.end());
  }
  return x;
}

void CoupledLoop::store() {
  const std::size_t comps = coupled_restart_components(rc_ != nullptr);
  std::vector<double> local(comps * static_cast<std::size_t>(count_));
  for (int k = 0; k < count_; ++k) {
    const std::size_t j = static_cast<std::size_t>(first_ + k);
    double* o = &local[comps * static_cast<std::size_t>(k)];
    rod::pack_node(state_.nodes[j], o);
    for (int c = 0; c < 3; ++c) o[rod::kPackedNodeValues + c] = r_[j](c);
    if (rc_) rc_->pack_node(first_ + k, o + rod::kPackedNodeValues + 3);
  }
  slots_.write(w_, state_.t, steps, restart_extra(), local);
  stored_ = std::chrono::steady_clock::now();
}

void CoupledLoop::restore(const output::RestartPoint& point) {
  const auto& x = point.extra;
  const std::size_t comps = point.components, n = state_.nodes.size();
  for (std::size_t j = 0; j < n; ++j)
    for (int c = 0; c < 3; ++c) r_[j](c) = point.state[comps * j + rod::kPackedNodeValues + static_cast<std::size_t>(c)];
  m_.sigma = x[extra::sigma];
  m_.speed = x[extra::speed];
  m_.drive_work = x[extra::drive_work];
  m_.dissipated = x[extra::dissipated];
  m_.friction_work = x[extra::friction_work];
  m_.stick_fraction = x[extra::stick];
  up_prev_ = x[extra::up_prev];
  up_time_ = x[extra::up_time];
  contact_.normal = Vec3(x[extra::normal], x[extra::normal + 1], x[extra::normal + 2]);
  contact_.tangential = x[extra::tangential];
  steps = static_cast<long>(x[extra::steps]);
  newton = static_cast<long>(x[extra::newton]);
  coupling = static_cast<long>(x[extra::coupling]);
  written_t_ = x[extra::written_t];
  events.clear();
  if (x[extra::event_count] > 0.0)
    events.push_back({x[extra::event_time], x[extra::event_position], load_.name,
                      kEventReasons[static_cast<std::size_t>(x[extra::event_reason])]});
  if (!rc_) return;
  std::vector<double> per_node(RodAdaptiveControl::kPerNode * n);
  for (std::size_t j = 0; j < n; ++j)
    std::copy_n(&point.state[comps * j + rod::kPackedNodeValues + 3], RodAdaptiveControl::kPerNode,
                &per_node[RodAdaptiveControl::kPerNode * j]);
  const auto p = x.begin() + static_cast<std::ptrdiff_t>(extra::fixed);
  const std::vector<double> mass_node(p, p + RodAdaptiveControl::kPerNode);
  const auto q = p + RodAdaptiveControl::kPerNode;
  const auto na = static_cast<std::ptrdiff_t>(*q);
  rc_->restore(rod_levels(state_), per_node, std::vector<double>(q + 1, q + 1 + na));
  mc_->restore(mass_level(m_), mass_node, std::vector<double>(q + 1 + na, x.end()));
}

// A step in which the friction stopped the mass (rod::CoupledMassState::stick_fraction): redone
// from (old, m_old) with the step shortened to the stop (secant on the length for sigma' = 0,
// from the linear zero of the step); the state at the stop and its length (0: stuck at the start).
double CoupledLoop::shorten_to_stop(const rod::RodState& old, const rod::CoupledMassState& m_old, double h) {
  double ha = h, va = m_.speed, hb = m_.stick_fraction * h;
  for (int it = 0; it < 8 && hb > 0.0; ++it) {
    state_ = old;
    m_ = m_old;
    if (!solve(hb)) fail(failure(old.t, hb) + " (the step shortened to the mass's stop)");
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

// The centreline, the contact and the events of a step from (old, m_old) to the current state.
void CoupledLoop::accepted(const rod::RodState& old, const rod::CoupledMassState& m_old, double h) {
  starting(old, m_old);  // a shortened step starts here too
  ++steps;
  const bool stuck = m_.sticks();
  if (stuck) h = shorten_to_stop(old, m_old, h);
  if (h > 0.0) step_events(old, m_old, h);
  if (stuck && events.empty()) events.push_back({state_.t, m_.sigma, load_.name, "stick"});
}

// The centreline, the contact and the events (leaving, lift-off) of a step of length h > 0.
void CoupledLoop::step_events(const rod::RodState& old, const rod::CoupledMassState& m_old, double h) {
  r_ = rod::advance_centreline_in_time(r_, old, state_);
  const rod::CoupledContact c =
      rod::step_contact(old, m_old, state_, m_, stepper_.coupled_mass(), stepper_.model().loads.gravity, h);
  const double L = sc_.rod.length;
  if (m_.sigma < 0.0 || m_.sigma > L) {  // left the rod in this step: the time where sigma crosses the end
    const double edge = m_.sigma < 0.0 ? 0.0 : L;
    const double te = old.t + h * (edge - m_old.sigma) / (m_.sigma - m_old.sigma);
    events.push_back({te, edge, load_.name, edge == 0.0 ? "left_rod_at_0" : "left_rod_at_L"});
  } else if (load_.contact == scene::Contact::unilateral && c.up < 0.0) {
    // lift-off: the zero of C . d2 between the steps' midpoints
    const double tm = old.t + 0.5 * h;
    const double t0 = steps > 1 ? up_time_ : tm, f = steps > 1 && up_prev_ > 0.0 ? up_prev_ / (up_prev_ - c.up) : 1.0;
    const double te = t0 + f * (tm - t0);
    const double se = te <= old.t ? m_old.sigma : m_old.sigma + (te - old.t) / h * (m_.sigma - m_old.sigma);
    events.push_back({te, se, load_.name, "lift_off"});
  }
  up_prev_ = c.up;
  up_time_ = old.t + 0.5 * h;
  contact_ = StepContact{c.normal, c.tangential};
}

void CoupledLoop::run_fixed() {
  for (long i = steps + 1; i <= g_.steps && events.empty(); ++i) {  // from the restart point's step
    const double h = g_.time(i) - state_.t;
    const rod::RodState old = state_;
    const rod::CoupledMassState m_old = m_;
    starting(old, m_old);
    if (!solve(h)) fail(failure(old.t, h) + "; reduce time.dt");
    accepted(old, m_old, h);
    if (i % sc_.output.every == 0 || i == g_.steps || !events.empty()) {
      write();
      store_if_due();
    }
    progress_.update(state_.t, i);
    check_interrupt(i < g_.steps);
  }
}

// One adaptive attempt of length h (step doubling while the history is short): true when
// accepted; otherwise the state is as before and rc.next_dt the step to try.
bool CoupledLoop::adaptive_step(double h) {
  RodAdaptiveControl &rc = *rc_, &mc = *mc_;
  const rod::RodState old = state_;
  const rod::CoupledMassState m_old = m_;
  starting(old, m_old);
  auto restore = [&] {
    state_ = old;
    m_ = m_old;
  };
  const double dt_min = rc.controller().parameters().dt_min;
  auto retry = [&](double next, const std::string& why) {
    restore();
    if (h <= dt_min * (1.0 + 1e-12))
      fail("adaptive time stepping (time.adaptive) at t = " + scene::format_number(old.t) + " s: " + why +
           " at the smallest step, time.adaptive.dt_min = " + scene::format_number(dt_min) + " s");
    rc.next_dt = std::min(next, h);
    return false;
  };
  const bool doubled = !rc.has_history();
  if (!solve(h)) return ++rc.totals().failed, retry(rc.controller().after_failure(h), failure(old.t, h));
  double err = 0.0;
  rod::RodState mid;
  rod::CoupledMassState m_mid;
  if (doubled) {
    const auto full = rod_levels(state_), full_m = mass_level(m_);
    restore();
    if (!solve(0.5 * h)) return ++rc.totals().failed, retry(rc.controller().after_failure(h), failure(old.t, 0.5 * h));
    mid = state_;
    m_mid = m_;
    if (!solve(0.5 * h)) return ++rc.totals().failed, retry(rc.controller().after_failure(h), failure(mid.t, 0.5 * h));
    err = std::max(rc.doubling_error(full, rod_levels(mid), rod_levels(state_), h),
                   mc.doubling_error(full_m, mass_level(m_mid), mass_level(m_), h));
  } else {
    err = std::max(rc.extrapolation_error(rod_levels(state_), h), mc.extrapolation_error(mass_level(m_), h));
  }
  // The Newton signal: iterations per rod solve (the step makes one per coupling iteration).
  const int per_solve = last_.newton_iterations / std::max(1, last_.coupling_iterations);
  const StepDecision d = rc.controller().decide(h, err, per_solve);
  if (!d.accept) return ++rc.totals().rejected, retry(d.next_dt, "the error estimate is " + std::to_string(err) +
                                                                      " times the tolerance");
  if (doubled) {
    const rod::RodState end = state_;
    const rod::CoupledMassState m_end = m_;
    for (int part = 0; part < 2; ++part) {  // the two half steps, in order
      state_ = part == 0 ? mid : end;
      m_ = part == 0 ? m_mid : m_end;
      accepted(part == 0 ? old : mid, part == 0 ? m_old : m_mid, 0.5 * h);
      rc.accept(rod_levels(state_), 0.5 * h);
      mc.accept(mass_level(m_), 0.5 * h);
      rc.totals().record_accepted(0.5 * h);
      if (!events.empty()) break;
    }
  } else {
    accepted(old, m_old, h);
    rc.accept(rod_levels(state_), h);
    mc.accept(mass_level(m_), h);
    rc.totals().record_accepted(h);
  }
  rc.next_dt = d.next_dt;
  return true;
}

void CoupledLoop::run_adaptive() {
  RodAdaptiveControl& rc = *rc_;
  const long every = sc_.output.every, outputs = (g_.steps + every - 1) / every;
  auto output_time = [&](long k) { return g_.time(std::min(k * every, g_.steps)); };
  long k = 1;  // the first output time after the current one (a restart point's time may lie a rounding below it)
  while (k <= outputs && output_time(k) - state_.t <= 1e-9 * g_.dt) ++k;
  while (k <= outputs && events.empty()) {
    const double target = output_time(k), proposed = rc.next_dt;
    const double h = StepController::landing_step(proposed, target - state_.t);
    if (!adaptive_step(h)) continue;
    rc.next_dt = StepController::after_landing(h, proposed, rc.next_dt);
    const bool landed = std::abs(target - state_.t) <= 1e-9 * h;
    if (landed) ++k;
    if (landed || !events.empty()) {
      write();
      store_if_due();
    }
    progress_.update(state_.t, steps, rc.next_dt, rc.totals());
    check_interrupt(k <= outputs);
  }
}

// The coupled mass of the rod's stepper, from its scene load.
rod::CoupledRodMass rod_mass(const scene::MovingLoadSpec& load) {
  return {load.mass, load.drive, load.resistance, load.friction,
          load.resistance_through == scene::ResistanceThrough::structure};
}

}  // namespace

void run_rod_coupled(const scene::Scene& sc, const RodSetup& setup, const TimeGrid& grid, const RunOptions& opt,
                     MPI_Comm comm) {
  const scene::MovingLoadSpec& load = *coupled_load(sc);
  const int rank = comm_rank(comm);
  check_coupled_rod(sc, setup.model);
  if (!opt.restart) precheck_planar(sc, setup.model);
  // The initial state, or the restart point's (the whole state on every rank).
  InitialState start;
  output::RestartPoint point;
  std::string source;
  if (opt.restart) {
    source = output::restart_source(opt.output);
    const bool adaptive = sc.time.adaptive.enabled;
    point = read_rod_restart_point(opt.output, source, static_cast<std::size_t>(sc.mesh.nodes),
                                   coupled_restart_components(adaptive), coupled_restart_components(!adaptive),
                                   adaptive, grid.dt, extra::dt);
    start.description = "restart";
    start.state.t = point.time;
    start.state.ds = sc.mesh.ds;
    for (std::size_t j = 0; j < static_cast<std::size_t>(sc.mesh.nodes); ++j)
      start.state.nodes.push_back(rod::unpack_node(&point.state[point.components * j]));
  } else {
    start = initial_state(sc, setup, comm);
  }
  const rod::CoupledRodMass mass = rod_mass(load);
  // The rod's steps on the distributed stepper, made from the model with the mass's loads.
  solver::DistributedCoupledRodSolve* rod_solve = nullptr;
  rod::CoupledRodStepper stepper(setup.model, mass, [&](rod::RodModel with_mass) {
    RodSetup s{std::move(with_mass), setup.solver};
    auto made = std::make_unique<solver::DistributedCoupledRodSolve>(make_stepper(sc, s, comm), comm);
    rod_solve = made.get();
    return made;
  });
  solver::RodStepper& st = rod_solve->stepper();
  st.set_state(start.state, start.first_node);
  rod::RodState state = st.gather_state();  // whole, on every rank
  start.state = rod::RodState();
  // The mass's loads lie in the plane of a planar rod (its weight, its inertia along the rod
  // and the resistance along d3): the path is chosen from the model without them. A restart
  // keeps the path of the run it continues.
  const int stored_path = opt.restart ? (point.extra[extra::planar] != 0.0 ? 1 : 0) : -1;
  const PathChoice path = choose_path(sc, setup.model, st, stored_path, comm);
  if (path.planar) st.set_planar(&path.symmetry);
  const std::string path_text = st.path_description() + "; " + path.detail;
  rod::CoupledMassState m{load.start, load.initial_velocity()};
  const int first = st.first_owned_node(), count = st.num_owned_nodes();
  CoupledRodOutputs outputs(sc, load, stepper.model(), first, count);
  if (opt.restart) {
    output::check_restart_outputs(source, outputs.probe_names(), outputs.field_names());
    source = output::move_aside_for_restart(opt.output, comm);
  }
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "rod", {}};
  info.attributes = {{"rod_path", path.planar ? "planar" : "3D"}, {"rod_path_detail", path_text + " (coupled_mass)"},
                     {"initial_state", start.description}};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, outputs.layout(), 1);
  writer.set_intervals(opt.flush_interval, writer.xdmf_interval());
  outputs.declare(writer);
  Progress progress(rank == 0 && progress_wanted(opt.quiet, opt.progress), "t", "s", grid.t_start, grid.t_end,
                    opt.progress_interval);
  CoupledLoop loop(sc, stepper, state, m, outputs, writer, opt, grid, path.planar, first, count, comm, progress);
  if (opt.restart) {
    output::copy_output_steps(source, writer, point.steps_written, outputs.probe_names(), outputs.field_names(),
                              static_cast<std::size_t>(first), static_cast<std::size_t>(count));
    loop.restore(point);
    loop.store();
    output::remove_restart_source(opt.output, comm);
  } else {
    loop.write();
    loop.store();
  }
  if (rank == 0 && !opt.quiet) {
    std::printf("rod scene '%s': %d nodes, up to %ld steps of dt = %.6g s to t = %.6g s%s; initial state: %s; coupled "
                "mass '%s' (partitioned iteration); linear solver: %s; path: %s\n",
                sc.file.c_str(), sc.mesh.nodes, grid.steps, grid.dt, grid.t_end,
                sc.time.adaptive.enabled ? " (adaptive: the first step and the output spacing)" : "",
                start.description.c_str(), load.name.c_str(), st.resolved_linear_solver().c_str(),
                path_text.c_str());
    if (opt.restart)
      std::printf("restart from %s: time step %ld at t = %.9g s, %zu output steps kept\n", opt.output.c_str(),
                  point.step, point.time, point.steps_written);
  }
  const auto wall = std::chrono::steady_clock::now();
  if (sc.time.adaptive.enabled)
    loop.run_adaptive();
  else
    loop.run_fixed();
  auto& events = loop.events;
  progress.done();
  add_time_limit_event(sc, events, state.t, m.sigma, opt.quiet || rank != 0);
  loop.store();  // the end: a restart of the complete file continues nothing
  writer.write_events(events);
  if (loop.adaptive_totals()) write_adaptive_totals(writer, *loop.adaptive_totals());
  writer.finish();
  if (rank == 0 && !opt.quiet) {
    std::printf("done: %ld steps, %ld coupling iterations, %ld Newton iterations", loop.steps, loop.coupling,
                loop.newton);
    if (!events.empty())
      std::printf("; ended by the event %s at t = %.9g s%s", events[0].reason.c_str(), events[0].time,
                  events[0].reason.rfind("left_rod", 0) == 0 || events[0].reason == "lift_off" ? " (interpolated)" : "");
    std::printf("; %zu output steps -> %s; time stepping %.3f s (wall, output included)\n", writer.steps_written(),
                opt.output.c_str(), std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count());
    if (!loop.adaptive_summary().empty()) std::printf("adaptive: %s\n", loop.adaptive_summary().c_str());
  }
}

}  // namespace traverse::app
