// A rod run with a coupled mass (issue 17, docs/rod.md "Coupled mass"): the serial reference
// stepper with the mass's position an unknown of each step (rod::CoupledRodStepper), on one rank.
// Outputs: the rod's probes and fields, the mass's probes (position, speed, fixed-frame position
// and velocity, contact forces), the energies, and the events table (the run ends when the mass
// leaves the rod).
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <sstream>

#include "interrupt.hpp"
#include "progress.hpp"
#include "rod_quantities.hpp"
#include "rod_setup.hpp"
#include "run.hpp"
#include "run_beam_coupled.hpp"
#include "run_rod_coupled.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/rod/coupled_mass_rod.hpp"
#include "traverse/version.hpp"

namespace traverse::app {

namespace {

constexpr int kMaxCoupledNodes = 2001;  // the reference stepper factorises the whole rod

}  // namespace

void check_coupled_rod(const scene::Scene& sc, const rod::RodModel& model, int ranks) {
  const scene::MovingLoadSpec& load = *coupled_load(sc);
  const std::string k = "loads." + load.name;
  if (ranks != 1)
    scene::fail_at(sc, k + ".type", "a run on 1 rank: a coupled_mass on the rod uses the serial reference stepper "
                   "(the distributed path is not yet supported)", std::to_string(ranks) + " ranks");
  const auto& a = model.alpha;
  for (double w : {a.as, a.bs, a.gs, a.at, a.bt, a.gt})
    if (w != 0.5)
      scene::fail_at(sc, "scheme.rho_inf", "rho_inf = rho_inf_space = 1 (all six parameters 1/2) with a coupled_mass "
                     "(its midpoint rule is the box scheme's; other parameters are not yet supported)",
                     "parameters (" + scene::format_number(a.as) + ", " + scene::format_number(a.bs) + ", " +
                         scene::format_number(a.gs) + ", " + scene::format_number(a.at) + ", " +
                         scene::format_number(a.bt) + ", " + scene::format_number(a.gt) + ")");
  if (sc.mesh.nodes > kMaxCoupledNodes)
    scene::fail_at(sc, sc.tree.params.sublist("mesh").isParameter("ds") ? "mesh.ds" : "mesh.nodes",
                   "at most " + std::to_string(kMaxCoupledNodes) + " nodes with a coupled_mass on the rod (the serial "
                   "reference stepper)", std::to_string(sc.mesh.nodes) + " nodes");
}

namespace {

/// The contact of the last step (NaN before the first).
struct StepContact {
  Vec3 normal = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  double tangential = std::numeric_limits<double>::quiet_NaN();
};

class CoupledRodOutputs {
 public:
  CoupledRodOutputs(const scene::Scene& sc, const scene::MovingLoadSpec& load, const rod::RodModel& model)
      : sc_(sc), load_(load), model_(model) {}
  output::NodeLayout layout() const {
    output::NodeLayout l;
    l.global_count = static_cast<size_t>(sc_.mesh.nodes);
    l.first = 0;
    l.count = l.global_count;
    for (int j = 0; j < sc_.mesh.nodes; ++j) l.s.push_back(j * sc_.mesh.ds);
    return l;
  }
  void declare(output::Writer& w) const;
  std::vector<std::string> probe_names() const;
  std::vector<std::string> field_names() const;
  /// Evaluates the outputs at a state, checks them against a restart's file, writes them.
  void write(output::Writer& w, const rod::RodState& s, const std::vector<Vec3>& r, const rod::CoupledMassState& m,
             const StepContact& c, const CoupledReplay& replay, MPI_Comm comm);

 private:
  const scene::Scene& sc_;
  const scene::MovingLoadSpec& load_;
  const rod::RodModel& model_;
  std::vector<std::vector<double>> probes_, fields_;
};

const char* const kMassProbes[] = {"_position", "_speed", "_fixed_position", "_fixed_velocity", "_normal_force",
                                    "_tangential_force"};
const char* const kEnergyProbes[] = {"energy_rod", "energy_rod_gravity", "energy_mass_kinetic", "energy_mass_gravity",
                                     "work_drive", "work_dissipated", "energy_balance"};

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
      {"energy_balance", "mechanical energy - work_drive + work_dissipated (constant up to the discretisation)"}};
  for (const auto& [name, what] : energies) w.add_probe({name, 1, "J", what, {}});
  for (const auto f : sc_.output.fields) {
    const RodFieldInfo fi = rod_field_info(f);
    w.add_field({scene::name_of(f), fi.components, fi.units, fi.description, fi.component_names, fi.geometry});
  }
}

void CoupledRodOutputs::write(output::Writer& w, const rod::RodState& s, const std::vector<Vec3>& r,
                              const rod::CoupledMassState& m, const StepContact& c, const CoupledReplay& replay,
                              MPI_Comm comm) {
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
  for (double v : {e.rod, e.rod_gravity, e.mass_kinetic, e.mass_gravity, e.drive_work, e.dissipated,
                   e.mechanical() - e.drive_work + e.dissipated})
    probes_.push_back({v});
  fields_.resize(sc_.output.fields.size());
  for (size_t f = 0; f < sc_.output.fields.size(); ++f) {
    const scene::Field field = sc_.output.fields[f];
    const size_t comps = field == scene::Field::R ? 9 : 3;
    fields_[f].resize(comps * static_cast<size_t>(N + 1));
    for (int j = 0; j <= N; ++j) {
      const auto& nd = s.nodes[static_cast<size_t>(j)];
      double* o = fields_[f].data() + comps * static_cast<size_t>(j);
      if (field == scene::Field::R) {
        for (int i = 0; i < 3; ++i)
          for (int k = 0; k < 3; ++k) o[3 * i + k] = nd.R(i, k);
      } else {
        const Vec3 v = quantity_value(field_quantity(field), view(j), model_.props, scene::Frame::body);
        std::copy(v.data(), v.data() + 3, o);
      }
    }
  }
  const std::size_t o = w.steps_written();
  if (o < replay.kept()) replay.check(o, s.t, probes_);
  std::vector<output::DoubleView> views(fields_.begin(), fields_.end());
  w.write_step(s.t, {m.sigma}, probes_, views);
  replay.written(w.steps_written(), comm);
}

}  // namespace

void run_rod_coupled(const scene::Scene& sc, const RodSetup& setup, const TimeGrid& grid, const RunOptions& opt,
                     MPI_Comm comm) {
  const scene::MovingLoadSpec& load = *coupled_load(sc);
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  check_coupled_rod(sc, setup.model, ranks);
  InitialState start = initial_state(sc, setup, comm);
  const rod::CoupledRodMass mass{load.mass, load.drive, load.resistance};
  rod::CoupledRodStepper stepper(setup.model, mass);
  rod::RodState state = start.state;
  rod::CoupledMassState m{load.start, load.initial_velocity()};
  std::vector<Vec3> r = rod::centreline_in_space(state);
  CoupledRodOutputs outputs(sc, load, stepper.model());
  const CoupledReplay replay(opt, outputs.probe_names(), outputs.field_names(), "the rod and its coupled mass", comm);
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "rod", {}};
  info.attributes = {{"rod_path", "3D"}, {"rod_path_detail", "3D, serial reference stepper (coupled_mass)"}};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, outputs.layout(), 1);
  outputs.declare(writer);
  outputs.write(writer, state, r, m, StepContact{}, replay, comm);
  if (!opt.quiet)
    std::printf("rod scene '%s': %d nodes, up to %ld steps of dt = %.6g s to t = %.6g s; initial state: %s; coupled mass "
                "'%s' on the serial reference stepper (partitioned iteration), 3D path\n",
                sc.file.c_str(), sc.mesh.nodes, grid.steps, grid.dt, grid.t_end, start.description.c_str(),
                load.name.c_str());
  Progress progress(progress_wanted(opt.quiet, opt.progress), "t", "s", grid.t_start, grid.t_end);
  const double L = sc.rod.length;
  std::vector<output::RunEvent> events;
  long newton = 0, coupling = 0, i = 1;
  const bool unilateral = load.contact == scene::Contact::unilateral;
  double up_prev = 0.0, up_time = 0.0;
  const auto wall = std::chrono::steady_clock::now();
  for (; i <= grid.steps && events.empty(); ++i) {
    const double h = grid.time(i) - state.t;
    const rod::RodState old = state;
    const rod::CoupledMassState m_old = m;
    const auto rep = stepper.step(state, m, h);
    if (!rep.converged) {
      std::ostringstream os;
      os.precision(9);
      os << "time step " << i << " (t = " << old.t << " s, dt = " << h << " s): the coupled step of rod and mass '"
         << load.name << "' did not converge (" << rep.coupling_iterations << " coupling iterations, last change "
         << rep.last_change << " ds); reduce time.dt";
      progress.done();
      writer.fail(os.str());
      throw NumericsError(os.str());
    }
    newton += rep.newton_iterations;
    coupling += rep.coupling_iterations;
    r = rod::advance_centreline_in_time(r, old, state);
    const rod::CoupledContact c = rod::step_contact(old, m_old, state, m, mass, stepper.model().loads.gravity, h);
    if (m.sigma < 0.0 || m.sigma > L) {  // left the rod in this step: the time where sigma crosses the end
      const double edge = m.sigma < 0.0 ? 0.0 : L;
      const double te = old.t + h * (edge - m_old.sigma) / (m.sigma - m_old.sigma);
      events.push_back({te, edge, load.name, edge == 0.0 ? "left_rod_at_0" : "left_rod_at_L"});
    } else if (unilateral && c.up < 0.0) {  // lift-off: the zero of C . d2 between the steps' midpoints
      const double tm = old.t + 0.5 * h;
      const double t0 = i > 1 ? up_time : tm, f = i > 1 && up_prev > 0.0 ? up_prev / (up_prev - c.up) : 1.0;
      const double te = t0 + f * (tm - t0);
      const double se = te <= old.t ? m_old.sigma : m_old.sigma + (te - old.t) / h * (m.sigma - m_old.sigma);
      events.push_back({te, se, load.name, "lift_off"});
    }
    up_prev = c.up;
    up_time = old.t + 0.5 * h;
    if (i % sc.output.every == 0 || i == grid.steps || !events.empty())
      outputs.write(writer, state, r, m, StepContact{c.normal, c.tangential}, replay, comm);
    progress.update(state.t, i);
    if (const int sig = i < grid.steps && events.empty() ? interrupt_requested(comm) : 0) {
      progress.done();
      const std::string msg = "interrupted at t = " + scene::format_number(state.t) + " s (" + signal_name(sig) +
                              "); continue with traverse run --restart " + opt.output;
      writer.fail(msg);
      throw Interrupted(sig, opt.output, msg, msg);
    }
  }
  progress.done();
  writer.write_events(events);
  writer.finish();
  replay.finished(writer.steps_written(), comm);
  if (!opt.quiet) {
    std::printf("done: %ld steps, %ld coupling iterations, %ld Newton iterations", i - 1, coupling, newton);
    if (!events.empty())
      std::printf("; ended by the event %s at t = %.9g s (interpolated)", events[0].reason.c_str(),
                  events[0].time);
    std::printf("; %zu output steps -> %s; time stepping %.3f s (wall, output included)\n", writer.steps_written(),
                opt.output.c_str(), std::chrono::duration<double>(std::chrono::steady_clock::now() - wall).count());
  }
}

}  // namespace traverse::app
