// What a beam run writes at an output step (beam_outputs.hpp).
#include "traverse/setup/beam_outputs.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "traverse/core/comm.hpp"

namespace traverse::setup {

namespace {

const char* const kBeamEnergyProbes[] = {"energy_beam_kinetic", "energy_beam_elastic", "energy_beam_gravity",
                                         "energy_mass_kinetic", "energy_mass_gravity", "work_drive",
                                         "work_dissipated", "work_friction", "energy_balance"};

}  // namespace

void ProbeTracker::take(double t, const std::vector<std::vector<double>>& probes) {
  last_t_ = t;
  if (e_.empty()) {
    const double nan = std::numeric_limits<double>::quiet_NaN();
    for (const auto& p : probes) e_.push_back({std::vector<double>(p.size(), nan), std::vector<double>(p.size(), nan),
                                               std::vector<double>(p.size(), nan), std::vector<double>(p.size(), nan)});
  }
  for (std::size_t i = 0; i < probes.size(); ++i)
    for (std::size_t c = 0; c < probes[i].size(); ++c) {
      const double v = probes[i][c];
      output::ProbeExtremes& e = e_[i];
      if (std::isnan(v)) continue;
      if (!(v >= e.min[c])) e.min[c] = v, e.time_of_min[c] = t;  // the first comparison is with NaN
      if (!(v <= e.max[c])) e.max[c] = v, e.time_of_max[c] = t;
    }
}

void ProbeTracker::write(output::Writer& w) const {
  for (std::size_t i = 0; i < e_.size(); ++i) w.write_probe_extremes(i, e_[i]);
}

BeamOutputs::BeamOutputs(const scene::Scene& sc, const beam::BeamProblem& p, const beam::ModeSet& modes, MPI_Comm comm)
    : sc_(sc), fields_(sc, p, modes, comm) {
  probes_.assign(sc.output.probes.size() + 2 * sc.loads.size(), std::vector<double>(1));
  sigma_.assign(std::max<size_t>(1, sc.loads.size()), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t i = 0, k = 0; i < sc.loads.size(); ++i) {
    first_.push_back(k);
    k += sc.loads[i].type == scene::LoadType::axle_train ? sc.loads[i].train_offsets.size() : 1;
  }
}

std::vector<std::string> BeamOutputs::probe_names() const {
  std::vector<std::string> names;
  for (const auto& pr : sc_.output.probes) names.push_back(pr.name);
  for (const auto& l : sc_.loads) {
    names.push_back(l.name + "_position");
    names.push_back(l.name + "_deflection");
  }
  return names;
}

std::vector<std::string> BeamOutputs::field_names() const { return fields_.names(); }

void BeamOutputs::declare(output::Writer& w) const {
  for (const auto& pr : sc_.output.probes) declare_beam_probe(w, pr);
  for (const auto& l : sc_.loads) {
    w.add_probe({l.name + "_position", 1, "m", "position x(t) of load '" + l.name + "' along the beam" +
                 (l.type == scene::LoadType::axle_train ? " (its head)" : ""), {}});
    w.add_probe({l.name + "_deflection", 1, "m",
                 "deflection w(x(t), t) under load '" + l.name + "' (NaN while it is off the beam)", {}});
  }
  fields_.declare(w);
}

void BeamOutputs::evaluate(const beam::BeamSnapshot& s) {
  evaluate_probes(s);
  fields_.evaluate(s.Y);
}

void BeamOutputs::evaluate_probes(const beam::BeamSnapshot& s) {
  size_t k = 0;
  for (const auto& pr : sc_.output.probes)
    probes_[k++][0] = pr.type == scene::ProbeType::acceleration ? s.acceleration(pr.at) : s.deflection(pr.at);
  for (size_t i = 0; i < sc_.loads.size(); ++i) {
    sigma_[i] = s.load_position(first_[i]);
    probes_[k++][0] = s.load_position(first_[i]);
    probes_[k++][0] = s.load_deflection(first_[i]);
  }
}

void BeamOutputs::write(output::Writer& w, double t) const {
  w.write_step(t, sigma_, probes_, fields_.views());
}

CoupledBeamOutputs::CoupledBeamOutputs(const scene::Scene& sc, const scene::MovingLoadSpec& load, const beam::BeamProblem& p,
                                       const beam::ModeSet& modes, MPI_Comm comm)
    : sc_(sc), load_(load), fields_(sc, p, modes, comm) {}


std::vector<std::string> CoupledBeamOutputs::probe_names() const {
  std::vector<std::string> names;
  for (const auto& pr : sc_.output.probes) names.push_back(pr.name);
  for (const char* q : {"_position", "_speed", "_deflection", "_fixed_position", "_fixed_velocity", "_normal_force",
                        "_tangential_force"})
    names.push_back(load_.name + q);
  for (const char* e : kBeamEnergyProbes) names.push_back(e);
  return names;
}

std::vector<std::string> CoupledBeamOutputs::field_names() const { return fields_.names(); }

void CoupledBeamOutputs::declare(output::Writer& w) const {
  for (const auto& pr : sc_.output.probes)
    w.add_probe({pr.name, 1, "m", "transverse deflection w (positive up, +j) at x = " + scene::format_number(pr.at) + " m",
                 {}});
  const std::string m = load_.name, q = "coupled mass '" + m + "'";
  w.add_probe({m + "_position", 1, "m", "position x(t) of " + q + " along the beam", {}});
  w.add_probe({m + "_speed", 1, "m/s", "speed x'(t) of " + q + " along the beam (signed)", {}});
  w.add_probe({m + "_deflection", 1, "m", "deflection w(x(t), t) under " + q, {}});
  w.add_probe({m + "_fixed_position", 3, "m", "fixed-frame position (x, w(x), 0) of " + q, {"x", "y", "z"}});
  w.add_probe({m + "_fixed_velocity", 3, "m/s", "fixed-frame velocity (x', w_t + x' w_x, 0) of " + q, {"x", "y", "z"}});
  w.add_probe({m + "_normal_force", 1, "N", "normal contact force of the beam on " + q + " (positive: pushes it up)", {}});
  w.add_probe({m + "_tangential_force", 1, "N", "tangential contact force of the beam on " + q + " (0 without friction)",
               {}});
  const std::pair<const char*, const char*> energies[] = {
      {"energy_beam_kinetic", "beam kinetic energy 1/2 int rhoA w_t^2 dx"},
      {"energy_beam_elastic", "beam bending energy 1/2 int EI w_xx^2 dx"},
      {"energy_beam_gravity", "beam gravity potential int rhoA g w dx"},
      {"energy_mass_kinetic", "kinetic energy of the coupled mass 1/2 M |p'|^2"},
      {"energy_mass_gravity", "gravity potential of the coupled mass M g w(x)"},
      {"work_drive", "work of the drive since the start, int D x' dt"},
      {"work_dissipated", "work dissipated by the resistance since the start, int c x'^2 dt"},
      {"work_friction", "work dissipated by the Coulomb friction since the start, int mu |N| |x'| dt"},
      {"energy_balance", "mechanical energy - work_drive + work_dissipated + work_friction (constant up to the time "
                         "discretisation)"}};
  for (const auto& [name, what] : energies) w.add_probe({name, 1, "J", what, {}});
  fields_.declare(w);
}

void CoupledBeamOutputs::evaluate(const beam::CoupledMassBeam& s) {
  evaluate_probes(s);
  fields_.evaluate(s.Y());
}

void CoupledBeamOutputs::evaluate_probes(const beam::CoupledMassBeam& s) {
  probes_.clear();
  for (const auto& pr : sc_.output.probes) probes_.push_back({s.deflection(pr.at)});
  const double x = s.position(), w = s.mass_deflection(), v = s.speed();
  probes_.push_back({x});
  probes_.push_back({v});
  probes_.push_back({w});
  probes_.push_back({x, w, 0.0});
  probes_.push_back({v, s.mass_vertical_velocity(), 0.0});
  probes_.push_back({s.normal_force()});
  probes_.push_back({s.tangential_force()});
  const beam::CoupledEnergies e = s.energies();
  for (double value : {e.beam_kinetic, e.beam_elastic, e.beam_gravity, e.mass_kinetic, e.mass_gravity, e.drive_work,
                       e.dissipated, e.friction_work, e.balance()})
    probes_.push_back({value});
  sigma_[0] = x;
}

std::vector<std::string> VehicleOutputs::probe_names() const {
  std::vector<std::string> names;
  for (const auto& pr : sc_.output.probes) names.push_back(pr.name);
  for (const auto* l : vehicles_) {
    for (const char* q : {"_position", "_deflection", "_body_displacement", "_body_acceleration"})
      names.push_back(l->name + q);
    if (l->type == scene::LoadType::vehicle) names.push_back(l->name + "_pitch");
    names.push_back(l->name + "_contact_force");
  }
  return names;
}

void VehicleOutputs::declare(output::Writer& w) const {
  for (const auto& pr : sc_.output.probes) declare_beam_probe(w, pr);
  for (const auto* l : vehicles_) {
    const std::string m = l->name, q = "of " + scene::name_of(l->type) + " '" + m + "'";
    w.add_probe({m + "_position", 1, "m", "position x(t) of the leading axle " + q + " along the beam", {}});
    w.add_probe({m + "_deflection", 1, "m", "deflection w(x(t), t) under the leading axle " + q + " (0 off the beam)",
                 {}});
    w.add_probe({m + "_body_displacement", 1, "m",
                 "body displacement z (up) " + q + ", from where it sits on undeformed ground with unloaded springs", {}});
    w.add_probe({m + "_body_acceleration", 1, "m/s^2", "body acceleration z'' (up) " + q, {}});
    if (l->type == scene::LoadType::vehicle)
      w.add_probe({m + "_pitch", 1, "rad", "body pitch theta " + q + " (positive: the front rises)", {}});
    std::vector<std::string> axles;
    for (std::size_t a = 0; a < l->axle_offsets.size(); ++a) axles.push_back("axle" + std::to_string(a + 1));
    w.add_probe({m + "_contact_force", axles.size(), "N",
                 "contact force on each axle " + q + " from the beam (or the ground off it), positive when compressive",
                 axles.size() > 1 ? axles : std::vector<std::string>{}});
  }
  fields_.declare(w);
}

void VehicleOutputs::evaluate(const beam::VehicleBeam& s) {
  evaluate_probes(s);
  fields_.evaluate(s.Y());
}

void VehicleOutputs::evaluate_probes(const beam::VehicleBeam& s) {
  probes_.clear();
  for (const auto& pr : sc_.output.probes)
    probes_.push_back({pr.type == scene::ProbeType::acceleration ? s.acceleration(pr.at) : s.deflection(pr.at)});
  for (std::size_t j = 0; j < vehicles_.size(); ++j) {
    const scene::MovingLoadSpec& l = *vehicles_[j];
    std::size_t lead = 0;
    for (std::size_t a = 1; a < l.axle_offsets.size(); ++a)
      if (l.axle_offsets[a] > l.axle_offsets[lead]) lead = a;
    const double x = s.axle_position(j, lead);
    sigma_[j] = x;
    probes_.push_back({x});
    probes_.push_back({x >= 0.0 && x <= sc_.beam.length ? s.deflection(x) : 0.0});
    probes_.push_back({s.body_displacement(j)});
    probes_.push_back({s.body_acceleration(j)});
    if (l.type == scene::LoadType::vehicle) probes_.push_back({s.body_pitch(j)});
    std::vector<double> f;
    for (std::size_t a = 0; a < l.axle_offsets.size(); ++a) f.push_back(s.contact_force(j, a));
    probes_.push_back(f);
  }
}

BeamNodeShapes::BeamNodeShapes(const scene::Scene& sc, const beam::BeamProblem& p, const beam::ModeSet& modes) {
  const auto nodes = static_cast<std::size_t>(sc.mesh.nodes);
  x.assign(p.quadrature_nodes.begin(), p.quadrature_nodes.begin() + static_cast<std::ptrdiff_t>(nodes));
  VecX dphi(modes.size()), ddphi(modes.size());
  phi.assign(nodes, VecX(modes.size()));
  for (std::size_t j = 0; j < nodes; ++j) modes.evaluate(x[j], phi[j], dphi, ddphi);
}

bool call_beam_back(const StepCallback& cb, long step, double t, const VecX& Y, const VecX& Ydot,
                    const BeamNodeShapes& shapes, MPI_Comm comm) {
  bool go = true;
  if (par::rank(comm) == 0) {
    BeamStepView v;
    v.t = t;
    v.step = step;
    v.q.assign(Y.data(), Y.data() + Y.size());
    v.q_t.assign(Ydot.data(), Ydot.data() + Ydot.size());
    v.x = shapes.x;
    v.w.resize(shapes.x.size());
    for (std::size_t j = 0; j < v.w.size(); ++j) v.w[j] = shapes.phi[j].dot(Y);  // as BeamFields::evaluate
    go = cb.beam(v);
  }
  return par::root_answer(go, comm);
}

}  // namespace traverse::setup
