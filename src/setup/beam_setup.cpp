// The beam models of a scene (beam_setup.hpp).
#include "traverse/setup/beam_setup.hpp"

#include <cmath>

#include "traverse/setup/beam_fields.hpp"
#include "traverse/setup/run_limits.hpp"
#include "traverse/setup/step_control.hpp"

namespace traverse::setup {

namespace {

beam::MovingLoad moving_load(const scene::MovingLoadSpec& l) {
  beam::MovingLoad m;
  m.kind = l.inertia ? beam::LoadKind::Mass : beam::LoadKind::Force;
  m.mass = l.mass;
  m.force = l.force.y();  // vertical, positive up (validated: no other components)
  m.entry = l.entry == scene::Entry::left ? beam::BeamEnd::Left : beam::BeamEnd::Right;
  m.direction = l.direction();
  m.speed = l.speed;
  m.acceleration = l.acceleration;
  m.entry_time = l.entry_time;
  m.start = l.start;
  return m;
}

/// The moving forces of an axle train: axle a, e_a behind the head, enters when the head has
/// travelled e_a, at the head's speed then.
void add_axle_train(const scene::MovingLoadSpec& l, std::vector<beam::MovingLoad>& loads) {
  for (std::size_t a = 0; a < l.train_offsets.size(); ++a) {
    beam::MovingLoad m = moving_load(l);
    m.kind = beam::LoadKind::Force;
    m.mass = 0.0;
    m.force = -l.train_loads[a];
    m.entry_time = l.travel_time(l.train_offsets[a]);
    m.speed = std::abs(l.velocity(m.entry_time));
    loads.push_back(m);
  }
}

}  // namespace

beam::BeamProblem beam_problem(const scene::Scene& sc, const CheckedRun& checked) {
  const TimeGrid& grid = checked.grid;
  const auto& b = sc.beam;
  beam::BeamProblem p;
  p.length = b.length;
  p.EI = b.youngs_modulus * b.section.I1;
  p.rhoA = b.density * b.section.area;
  p.support = beam_support(b.supports);
  p.n_modes = b.modes;
  p.quadrature_nodes.resize(static_cast<size_t>(sc.mesh.nodes));
  for (int j = 0; j < sc.mesh.nodes; ++j) p.quadrature_nodes[static_cast<size_t>(j)] = j * sc.mesh.ds;
  p.quadrature_nodes.back() = b.length;
  p.gauss_points = b.quadrature_points;
  p.gravity = sc.gravity;
  p.self_weight = b.self_weight;
  p.initial_state = beam::InitialState::Static;
  for (const auto& l : sc.loads) {
    if (l.type == scene::LoadType::axle_train)
      add_axle_train(l, p.loads);
    else if (!l.suspended())  // vehicles on suspensions: run_beam_vehicles
      p.loads.push_back(moving_load(l));
  }
  p.damping = beam_damping(b);
  for (const auto& pr : sc.output.probes) p.accelerations |= pr.type == scene::ProbeType::acceleration;
  p.t_start = grid.t_start;
  p.t_end = grid.t_end;
  p.dt = grid.dt;
  p.integrator = b.integrator == scene::BeamIntegrator::newmark ? beam::Integrator::Newmark : beam::Integrator::RK4;
  p.output_every = checked.output_every;
  p.adaptive = sc.time.adaptive.enabled;
  if (p.adaptive) p.control = step_control_parameters(sc.time.adaptive, grid.dt, p.integrator == beam::Integrator::RK4 ? 4 : 2);
  return p;
}

beam::CoupledMass coupled_mass(const scene::MovingLoadSpec& l) {
  beam::CoupledMass m;
  m.mass = l.mass;
  m.start = l.start;
  m.velocity = l.initial_velocity();
  m.drive = l.drive;
  m.resistance = l.resistance;
  m.friction = l.friction;
  m.unilateral = l.contact == scene::Contact::unilateral;
  return m;
}

beam::Vehicle vehicle(const scene::MovingLoadSpec& l) {
  beam::Vehicle v;
  v.name = l.name;
  v.mass = l.mass;
  v.pitch_inertia = l.pitch_inertia;
  for (std::size_t a = 0; a < l.axle_offsets.size(); ++a)
    v.axles.push_back({l.axle_offsets[a], l.axle_stiffness[a], l.axle_damping[a], l.wheel_masses[a]});
  v.motion.entry = l.entry == scene::Entry::left ? beam::BeamEnd::Left : beam::BeamEnd::Right;
  v.motion.direction = l.direction();
  v.motion.speed = l.speed;
  v.motion.acceleration = l.acceleration;
  v.motion.entry_time = l.entry_time;
  v.motion.start = l.start;
  v.unilateral = l.contact == scene::Contact::unilateral;
  return v;
}

}  // namespace traverse::setup
