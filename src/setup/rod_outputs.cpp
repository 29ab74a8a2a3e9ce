// What a rod run writes at an output step (rod_outputs.hpp).
#include "traverse/setup/rod_outputs.hpp"

#include <algorithm>
#include <limits>

#include "traverse/core/comm.hpp"
#include "traverse/rod/coupled_mass_rod.hpp"
#include "traverse/setup/rod_quantities.hpp"
#include "traverse/setup/rod_setup.hpp"

namespace traverse::setup {

namespace {

// The scene's fields at `count` nodes (node_at(k): the view of the k-th), per node the field's
// rod_field_info components (field_values): a quantity's 3 values in the body frame, the 9
// entries of R row by row, or the one value of stretch and axial_force.
template <class NodeAt>
void evaluate_rod_fields(const std::vector<scene::Field>& fields, int count, const NodeAt& node_at,
                         const rod::RodProperties& props, std::vector<std::vector<double>>& values) {
  values.resize(fields.size());
  for (size_t f = 0; f < fields.size(); ++f) {
    const size_t comps = rod_field_info(fields[f]).components;
    values[f].resize(comps * static_cast<size_t>(count));
    for (int k = 0; k < count; ++k)
      field_values(fields[f], node_at(k), props, values[f].data() + comps * static_cast<size_t>(k));
  }
}

const char* const kMassProbes[] = {"_position", "_speed", "_fixed_position", "_fixed_velocity", "_normal_force",
                                    "_tangential_force"};
const char* const kRodEnergyProbes[] = {"energy_rod", "energy_rod_gravity", "energy_mass_kinetic", "energy_mass_gravity",
                                        "work_drive", "work_dissipated", "work_friction", "energy_balance"};
const char* const kBodyProbes[] = {"_body_displacement", "_body_acceleration", "_contact_force"};
const char* const kBodyEnergyProbes[] = {"energy_body", "work_damper"};

}  // namespace

RodOutputs::RodOutputs(const scene::Scene& sc, const rod::RodModel& model, const solver::RodStepper& st,
                       MPI_Comm comm)
    : sc_(sc), model_(model), st_(st), comm_(comm), num_cells_(sc.mesh.nodes - 1), first_(st.first_owned_node()),
      count_(st.num_owned_nodes()) {
  // What the outputs read at an output step: the nodes around the probes, and the centreline
  // (each rank its own nodes) only for a position probe or the field r.
  std::vector<rod::PointOutput> points;
  for (const auto& pr : sc.output.probes) points.push_back({pr.at, pr.quantity == scene::Quantity::position});
  bool r_field = false;
  for (const auto f : sc.output.fields) r_field = r_field || f == scene::Field::r;
  needs_ = rod::output_needs(num_cells_, sc.mesh.ds, points, r_field);
  probe_values_.assign(sc.output.probes.size() + sc.loads.size(), std::vector<double>(1));
  for (size_t i = 0; i < sc.output.probes.size(); ++i) probe_values_[i].assign(3, 0.0);
  field_values_.resize(sc.output.fields.size());
  sigma_.assign(std::max<size_t>(1, sc.loads.size()), std::numeric_limits<double>::quiet_NaN());
}

std::vector<std::string> RodOutputs::probe_names() const {
  std::vector<std::string> names;
  for (const auto& pr : sc_.output.probes) names.push_back(pr.name);
  for (const auto& l : sc_.loads) names.push_back(l.name + "_position");
  return names;
}

std::vector<std::string> RodOutputs::field_names() const {
  std::vector<std::string> names;
  for (const auto f : sc_.output.fields) names.push_back(scene::name_of(f));
  return names;
}

output::NodeLayout RodOutputs::layout() const {
  output::NodeLayout layout;
  layout.global_count = static_cast<size_t>(num_cells_ + 1);
  layout.first = static_cast<size_t>(first_);
  layout.count = static_cast<size_t>(count_);
  for (int k = 0; k < count_; ++k) layout.s.push_back((first_ + k) * sc_.mesh.ds);
  return layout;
}

void RodOutputs::declare(output::Writer& w) const {
  declare_rod_probes(w, sc_.output.probes);
  for (const auto& l : sc_.loads)
    w.add_probe({l.name + "_position", 1, "m", "arclength sigma(t) of load '" + l.name + "'", {}});
  for (const auto f : sc_.output.fields) {
    const RodFieldInfo fi = rod_field_info(f);
    w.add_field({scene::name_of(f), fi.components, fi.units, fi.description, fi.component_names, fi.geometry});
  }
}

void RodOutputs::evaluate_probes(const std::vector<rod::RodNode>& near, const std::vector<Vec3>& near_r) {
  auto view = [&](int j) {
    const auto i = static_cast<size_t>(std::lower_bound(needs_.nodes.begin(), needs_.nodes.end(), j) - needs_.nodes.begin());
    return node_view(near[i], near_r.empty() ? Vec3::Zero() : near_r[i]);
  };
  for (size_t i = 0; i < sc_.output.probes.size(); ++i) {
    const auto& pr = sc_.output.probes[i];
    const Vec3 v = quantity_at(pr.quantity, pr.at, sc_.mesh.ds, num_cells_, model_.props, pr.frame, view);
    probe_values_[i].assign(v.data(), v.data() + 3);
  }
}

void RodOutputs::evaluate_fields(const std::vector<Vec3>& r) {
  auto view = [&](int k) {
    return node_view(st_.owned_node(k), r.empty() ? Vec3::Zero() : r[static_cast<size_t>(k)]);
  };
  evaluate_rod_fields(sc_.output.fields, count_, view, model_.props, field_values_);
}

// The centreline at this rank's nodes from r(0) = r0: each rank sums up its piece, the
// summaries of all ranks give each its start (rod::centreline_starts), and it integrates its
// own nodes from there.
std::vector<Vec3> RodOutputs::owned_centreline(const Vec3& r0) const {
  std::vector<Vec3> t(static_cast<size_t>(count_));
  for (int k = 0; k < count_; ++k) t[static_cast<size_t>(k)] = rod::tangent(st_.owned_node(k), model_.props);
  const rod::CentrelinePiece mine = rod::centreline_piece(t, first_, model_.ds(), first_ == 0 ? r0 : Vec3::Zero());
  const int rank = par::rank(comm_);
  std::vector<rod::CentrelinePiece> all(static_cast<size_t>(par::size(comm_)));
  par::allgather_bytes(&mine, sizeof mine, all.data(), comm_);
  return rod::centreline_from(t, model_.ds(), rod::centreline_starts(all, model_.ds(), r0)[static_cast<size_t>(rank)]);
}

// r at the nodes the probes read (needs_.nodes), on every rank, from their owners' `r`.
std::vector<Vec3> RodOutputs::near_positions(const std::vector<Vec3>& r) const {
  const std::vector<int>& wanted = needs_.nodes;
  std::vector<double> local(3 * wanted.size(), 0.0), all(local.size());
  for (size_t i = 0; i < wanted.size(); ++i)
    if (wanted[i] >= first_ && wanted[i] < first_ + count_) {
      const Vec3& p = r[static_cast<size_t>(wanted[i] - first_)];
      std::copy(p.data(), p.data() + 3, &local[3 * i]);
    }
  par::allreduce(local.data(), all.data(), static_cast<int>(local.size()), MPI_DOUBLE, MPI_SUM, comm_);
  std::vector<Vec3> out(wanted.size());
  for (size_t i = 0; i < wanted.size(); ++i) out[i] = Vec3(all[3 * i], all[3 * i + 1], all[3 * i + 2]);
  return out;
}

void RodOutputs::write(output::Writer& w, double t, const Vec3& r0) {
  std::vector<Vec3> r, near_r;     // r at the owned nodes and at needs_.nodes (with the centreline)
  std::vector<rod::RodNode> near;  // needs_.nodes
  if (needs_.centreline) r = owned_centreline(r0);
  if (!needs_.nodes.empty()) {
    near = gather_nodes(st_, needs_.nodes, comm_);
    if (needs_.centreline) near_r = near_positions(r);
  }
  evaluate_probes(near, near_r);
  for (size_t i = 0; i < sc_.loads.size(); ++i) {
    sigma_[i] = sc_.loads[i].sigma(t);
    probe_values_[sc_.output.probes.size() + i][0] = sigma_[i];
  }
  evaluate_fields(r);
  std::vector<output::DoubleView> views(field_values_.begin(), field_values_.end());
  w.write_step(t, sigma_, probe_values_, views);
}

namespace {
// A node of a step callback's view as plain numbers: r (3), the rows of R (9), y (12).
constexpr int kViewPerNode = 24;
void pack_view_node(double* o, const Vec3& r, const rod::RodNode& nd) {
  for (int i = 0; i < 3; ++i) o[i] = r(i);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) o[3 + 3 * i + j] = nd.R(i, j);
  for (int i = 0; i < 12; ++i) o[12 + i] = nd.y[i];
}

// The view of `nodes` packed nodes (pack_view_node) at step `step`, time t.
RodStepView rod_view(const std::vector<double>& all, int nodes, long step, double t) {
  RodStepView v;
  v.t = t;
  v.step = step;
  v.nodes = nodes;
  auto take = [&](std::vector<double>& out, int offset, int count) {
    out.resize(static_cast<size_t>(count) * static_cast<size_t>(nodes));
    for (int j = 0; j < nodes; ++j)
      for (int i = 0; i < count; ++i)
        out[static_cast<size_t>(count * j + i)] = all[static_cast<size_t>(kViewPerNode * j + offset + i)];
  };
  take(v.r, 0, 3);
  take(v.directors, 3, 9);
  take(v.u, 12, 3);
  take(v.omega, 15, 3);
  take(v.kappa, 18, 3);
  take(v.n, 21, 3);
  return v;
}
}  // namespace

bool RodOutputs::call_back(const StepCallback& cb, long step, double t, const Vec3& r0) const {
  const int nodes = model_.num_cells + 1;
  // Each rank's nodes in their places, zero elsewhere, summed on rank 0.
  std::vector<double> mine(static_cast<size_t>(kViewPerNode) * static_cast<size_t>(nodes), 0.0), all;
  const std::vector<Vec3> r = owned_centreline(r0);
  for (int k = 0; k < count_; ++k)
    pack_view_node(&mine[static_cast<size_t>(kViewPerNode) * static_cast<size_t>(first_ + k)], r[static_cast<size_t>(k)],
                   st_.owned_node(k));
  const int rank = par::rank(comm_);
  if (rank == 0) all.resize(mine.size());
  if (par::alone(comm_)) all = mine;
  else MPI_Reduce(mine.data(), all.data(), static_cast<int>(mine.size()), MPI_DOUBLE, MPI_SUM, 0, comm_);
  return par::root_answer(rank != 0 || cb.rod(rod_view(all, nodes, step, t)), comm_);
}

bool coupled_call_back(const StepCallback& cb, long step, const rod::RodState& s, const std::vector<Vec3>& r,
                       const rod::CoupledMassState& m, bool suspended, MPI_Comm comm) {
  if (par::rank(comm) != 0) return par::root_answer(true, comm);
  const int nodes = static_cast<int>(s.nodes.size());
  std::vector<double> all(static_cast<size_t>(kViewPerNode) * static_cast<size_t>(nodes));
  for (int j = 0; j < nodes; ++j)
    pack_view_node(&all[static_cast<size_t>(kViewPerNode * j)], r[static_cast<size_t>(j)], s.nodes[static_cast<size_t>(j)]);
  RodStepView v = rod_view(all, nodes, step, s.t);
  v.has_mass = true;
  v.sigma = m.sigma;
  v.speed = m.speed;
  v.has_body = suspended;
  if (suspended) v.body = m.body, v.body_speed = m.body_speed;
  return par::root_answer(cb.rod(v), comm);
}

rod::CoupledRodMass coupled_rod_mass(const scene::MovingLoadSpec& load) {
  if (load.type != scene::LoadType::sprung_mass)
    return {load.mass, load.drive, load.resistance, load.friction,
            load.resistance_through == scene::ResistanceThrough::structure, {}, {}, false, {}};
  rod::CoupledRodMass m;
  m.mass = load.wheel_masses.at(0);
  m.path_sigma = [load](double t) { return load.position(t); };
  m.path_speed = [load](double t) { return load.velocity(t); };
  m.suspended = true;
  m.suspension = {load.mass, load.axle_stiffness.at(0), load.axle_damping.at(0), Vec3::UnitY()};
  return m;
}

std::vector<std::string> CoupledRodOutputs::probe_names() const {
  std::vector<std::string> names;
  for (const auto& pr : sc_.output.probes) names.push_back(pr.name);
  for (const char* q : kMassProbes) names.push_back(load_.name + q);
  if (mass_.suspended)
    for (const char* q : kBodyProbes) names.push_back(load_.name + q);
  for (const char* e : kRodEnergyProbes) names.push_back(e);
  if (mass_.suspended)
    for (const char* e : kBodyEnergyProbes) names.push_back(e);
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
  const std::string n = load_.name, q = (mass_.suspended ? "the wheel of sprung mass '" : "coupled mass '") + n + "'";
  w.add_probe({n + "_position", 1, "m", "arclength sigma(t) of " + q, {}});
  w.add_probe({n + "_speed", 1, "m/s", "speed sigma'(t) of " + q + " along the rod (signed)", {}});
  w.add_probe({n + "_fixed_position", 3, "m", "fixed-frame position r(sigma) of " + q, xyz});
  w.add_probe({n + "_fixed_velocity", 3, "m/s", "fixed-frame velocity p' = U + sigma' d3 of " + q, xyz});
  w.add_probe({n + "_normal_force", 3, "N", "normal contact force of the rod on " + q +
               ", fixed frame, over the step ending here (NaN at t = 0)", xyz});
  w.add_probe({n + "_tangential_force", 1, "N", "tangential contact force of the rod on " + q +
               (mass_.prescribed() ? " (the traction that keeps its path" : " (0 without friction") + "; NaN at t = 0)", {}});
  if (mass_.suspended) {
    w.add_probe({n + "_body_displacement", 1, "m", "body displacement z along j of sprung mass '" + n +
                 "', from its place at rest over the wheel's start with an unloaded spring", {}});
    w.add_probe({n + "_body_acceleration", 1, "m/s^2", "body acceleration z'' along j of sprung mass '" + n + "'", {}});
    w.add_probe({n + "_contact_force", 1, "N", "contact force of the rod on sprung mass '" + n +
                 "' along d2 over the step ending here (positive: pushes it towards +d2; NaN at t = 0)", {}});
  }
  const std::pair<const char*, const char*> energies[] = {
      {"energy_rod", "rod kinetic + elastic energy (discrete_energy, cell averages)"},
      {"energy_rod_gravity", "rod gravity potential, -int rhoA g . r ds"},
      {"energy_mass_kinetic", "kinetic energy of the coupled mass 1/2 M |p'|^2"},
      {"energy_mass_gravity", "gravity potential of the coupled mass -M g . r(sigma)"},
      {"work_drive", "work of the drive since the start"},
      {"work_dissipated", "work dissipated by the resistance since the start"},
      {"work_friction", "work dissipated by the Coulomb friction since the start, int mu |C_perp| |sigma'| dt"},
      {"energy_balance", "mechanical energy - work_drive + work_dissipated + work_friction (+ energy_body + "
                         "work_damper with a suspension; constant up to the discretisation)"}};
  for (const auto& [name, what] : energies) w.add_probe({name, 1, "J", what, {}});
  if (mass_.suspended) {
    w.add_probe({"energy_body", 1, "J", "the sprung body's kinetic, spring and gravity energy 1/2 M_v z'^2 + 1/2 k e^2 "
                 "+ M_v g z", {}});
    w.add_probe({"work_damper", 1, "J", "work dissipated by the suspension's damper since the start", {}});
  }
  for (const auto f : sc_.output.fields) {
    const RodFieldInfo fi = rod_field_info(f);
    w.add_field({scene::name_of(f), fi.components, fi.units, fi.description, fi.component_names, fi.geometry});
  }
}

void CoupledRodOutputs::write(output::Writer& w, const rod::RodState& s, const std::vector<Vec3>& r,
                              const rod::CoupledMassState& m, const solver::ContactHistory& c) {
  probes_.clear();
  const int N = s.num_cells();
  auto view = [&](int j) { return node_view(s.nodes[static_cast<size_t>(j)], r[static_cast<size_t>(j)]); };
  for (const auto& pr : sc_.output.probes) {
    const Vec3 v = quantity_at(pr.quantity, pr.at, sc_.mesh.ds, N, model_.props, pr.frame, view);
    probes_.push_back({v.x(), v.y(), v.z()});
  }
  const rod::NodeInterpolation at = rod::locate_on_nodes(m.sigma, s.ds, N);
  const Vec3 rp = (1.0 - at.xi) * r[static_cast<size_t>(at.j)] + at.xi * r[static_cast<size_t>(at.j + 1)];
  const Vec3 pv = rod::mass_velocity(s, m, model_.props);
  probes_.push_back({m.sigma});
  probes_.push_back({m.speed});
  probes_.push_back({rp.x(), rp.y(), rp.z()});
  probes_.push_back({pv.x(), pv.y(), pv.z()});
  probes_.push_back({c.normal.x(), c.normal.y(), c.normal.z()});
  probes_.push_back({c.tangential});
  if (mass_.suspended) {
    probes_.push_back({m.body});
    probes_.push_back({rod::body_acceleration(mass_, model_.loads.gravity, m)});
    probes_.push_back({std::isnan(c.tangential) ? c.tangential : c.up_prev});
  }
  const auto e = rod::coupled_energies(model_, s, r, m, mass_);
  for (double v : {e.rod, e.rod_gravity, e.mass_kinetic, e.mass_gravity, e.drive_work, e.dissipated, e.friction_work,
                   e.balance()})
    probes_.push_back({v});
  if (mass_.suspended) {
    probes_.push_back({e.body});
    probes_.push_back({e.damper_work});
  }
  auto owned_view = [&](int k) { return view(first_ + k); };
  evaluate_rod_fields(sc_.output.fields, count_, owned_view, model_.props, fields_);
  std::vector<output::DoubleView> views(fields_.begin(), fields_.end());
  w.write_step(s.t, {m.sigma}, probes_, views);
}

}  // namespace traverse::setup
