#include "traverse/rod/coupled_mass_rod.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace traverse::rod {

Vec3 node_tangent(const RodNode& node, const RodProperties& props) {
  if (!props.compliant()) return node.R.row(2).transpose();
  return node.R.transpose() * props.strain(node.y.segment<3>(var::n), node.yt.segment<3>(var::n));
}

RodPointKinematics point_kinematics(const RodState& state, double sigma, const RodProperties& props) {
  const NodeInterpolation at = locate_on_nodes(sigma, state.ds, state.num_cells());
  const RodNode& a = state.nodes[static_cast<size_t>(at.j)];
  const RodNode& b = state.nodes[static_cast<size_t>(std::min(at.j + 1, state.num_cells()))];
  RodPointKinematics k;
  k.U = (1.0 - at.xi) * fixed_velocity(a) + at.xi * fixed_velocity(b);
  k.d3 = (1.0 - at.xi) * node_tangent(a, props) + at.xi * node_tangent(b, props);
  return k;
}

Vec3 mass_velocity(const RodState& state, const CoupledMassState& m, const RodProperties& props) {
  const RodPointKinematics k = point_kinematics(state, m.sigma, props);
  return k.U + m.speed * k.d3;
}

/// The mass's path during the step being solved (read by the MovingMass and the resistance's
/// point force): linear in t from the old to the new level.
struct CoupledRodStepper::Path {
  double t_old = 0.0, t_new = 0.0, dt = 1.0;
  double s_old = 0.0, s_new = 0.0, v_old = 0.0, v_new = 0.0;
  double force = 0.0;  ///< a suspension's force k e + c e' on the rod over the step (latest iterate)
  Vec3 d3 = Vec3::UnitZ();  ///< tangent at sigma for the resistance (latest iterate)
  double at(double t, double a, double b) const {
    if (t == t_new) return b;
    if (t == t_old) return a;
    return a + (t - t_old) / dt * (b - a);
  }
};

CoupledRodStepper::~CoupledRodStepper() = default;

CoupledRodStepper::CoupledRodStepper(RodModel model, CoupledRodMass mass, const CoupledRodSolveFactory& make)
    : path_(std::make_shared<Path>()), mass_(mass) {
  if (mass_.suspended ? !(mass_.mass >= 0.0) : !(mass_.mass > 0.0))
    throw std::invalid_argument("CoupledRodStepper: mass must be > 0 (>= 0 under a suspension)");
  if (mass_.suspended && (!mass_.prescribed() || !(mass_.suspension.body_mass > 0.0) ||
                          !(mass_.suspension.stiffness > 0.0) || !(mass_.suspension.damping >= 0.0)))
    throw std::invalid_argument("CoupledRodStepper: a suspension needs a prescribed path, body mass and stiffness > 0, "
                                "damping >= 0");
  if (mass_.prescribed() && (mass_.drive != 0.0 || mass_.resistance != 0.0 || mass_.friction != 0.0 || !mass_.path_speed))
    throw std::invalid_argument("CoupledRodStepper: a prescribed path needs its speed and no drive, resistance or friction");
  if (!(mass_.resistance >= 0.0)) throw std::invalid_argument("CoupledRodStepper: resistance must be >= 0");
  if (!(mass_.friction >= 0.0) || !std::isfinite(mass_.friction))
    throw std::invalid_argument("CoupledRodStepper: friction must be finite and >= 0");
  const std::shared_ptr<const Path> p = path_;
  MovingMass mm;
  mm.mass = mass_.mass;
  mm.sigma = [p](double t) { return p->at(t, p->s_old, p->s_new); };
  mm.speed = [p](double t) { return p->at(t, p->v_old, p->v_new); };
  mm.accel = [p](double) { return (p->v_new - p->v_old) / p->dt; };
  mm.inertia = true;
  if (mass_.suspended) {  // the body rides with the wheel across up
    mm.carried = mass_.suspension.body_mass;
    mm.carried_axis = mass_.suspension.up;
    mm.mass += mm.carried;
  }
  model.loads.masses.push_back(mm);
  if (mass_.suspended) {
    const Vec3 up = mass_.suspension.up;
    PointForce f;
    f.sigma = mm.sigma;
    f.force_fixed = [p, up](double) -> Vec3 { return p->force * up; };  // constant over the step: the body's impulse
    model.loads.point_forces.push_back(f);
  }
  if (air_resistance()) {
    const double c = mass_.resistance;
    PointForce f;
    f.sigma = mm.sigma;
    f.force_fixed = [p, c](double t) -> Vec3 { return -c * p->at(t, p->v_old, p->v_new) * p->d3; };
    model.loads.point_forces.push_back(f);
  }
  model_ = model;
  if (!make) throw std::invalid_argument("CoupledRodStepper: no rod solve");
  solve_ = make(std::move(model));
}

namespace {

// The part across d3m of M (p'_new - p'_old) / dt - M g: the normal contact force of a step
// (drive, resistance and friction act along d3m).
Vec3 normal_part(const RodPointKinematics& ko, double v_old, const RodPointKinematics& kn, double v_new,
                 const Vec3& d3m, double M, const Vec3& g, double dt) {
  const Vec3 C = M * ((kn.U + v_new * kn.d3) - (ko.U + v_old * ko.d3)) / dt - M * g;
  return C - C.dot(d3m) * d3m;
}

double sign(double x) { return x > 0.0 ? 1.0 : (x < 0.0 ? -1.0 : 0.0); }

// M (p'_new - p'_old) / dt - M g, dp the change of p' over the step: with a suspension plus the
// body's momentum change across up and minus the spring's force along up (`spring`).
Vec3 momentum_balance(const CoupledRodMass& mass, const Vec3& dp, const Vec3& g, double spring, double dt) {
  Vec3 C = mass.mass * (dp / dt - g);
  if (mass.suspended) {
    const Vec3& up = mass.suspension.up;
    C += mass.suspension.body_mass * (dp - up * up.dot(dp)) / dt - spring * up;
  }
  return C;
}

/// The body's new level from the wheel's velocity along up at the new level (the midpoint rule
/// of the suspension's equation, header): z, z', w, w' and the force k e_mid + c e'_mid on the
/// rod over the step (the body's impulse).
struct BodyLevel {
  double z = 0.0, zt = 0.0, w = 0.0, wt = 0.0, force = 0.0, damper_work = 0.0;
};
BodyLevel body_level(const Suspension& s, const Vec3& g, const CoupledMassState& m, double wheel_speed_new, double dt) {
  const double M = s.body_mass, k = s.stiffness, c = s.damping, gu = g.dot(s.up);
  BodyLevel b;
  b.wt = wheel_speed_new;
  b.w = m.wheel + 0.5 * dt * (m.wheel_speed + b.wt);
  const double e_old = m.body - m.wheel, et_old = m.body_speed - m.wheel_speed;
  // e_new = z_old + dt/2 (z'_old + z'_new) - w_new, e'_new = z'_new - w'_new: linear in z'_new
  b.zt = (M * m.body_speed + dt * (-0.5 * k * (e_old + m.body + 0.5 * dt * m.body_speed - b.w) -
                                   0.5 * c * (et_old - b.wt) + M * gu)) /
         (M + 0.25 * k * dt * dt + 0.5 * c * dt);
  b.z = m.body + 0.5 * dt * (m.body_speed + b.zt);
  const double et_mid = 0.5 * (et_old + b.zt - b.wt);
  b.force = M * gu - M * (b.zt - m.body_speed) / dt;
  b.damper_work = dt * c * et_mid * et_mid;
  return b;
}

}  // namespace

void start_suspension(const CoupledRodMass& mass, const RodModel& model, const RodState& state, CoupledMassState& m) {
  const Suspension& s = mass.suspension;
  const double e = s.body_mass * model.loads.gravity.dot(s.up) / s.stiffness;
  m.wheel = 0.0;
  m.wheel_speed = s.up.dot(mass_velocity(state, m, model.props));
  m.body = e;
  m.body_speed = m.wheel_speed;
  m.spring_force = s.stiffness * e;
}

double body_acceleration(const CoupledRodMass& mass, const Vec3& gravity, const CoupledMassState& m) {
  const Suspension& s = mass.suspension;
  const double e = m.body - m.wheel, et = m.body_speed - m.wheel_speed;
  return (-s.stiffness * e - s.damping * et) / s.body_mass + gravity.dot(s.up);
}

/// v_new of a step and what the friction did in it.
struct CoupledRodStepper::Speed {
  double v = 0.0;
  double stick_fraction = -1.0;  ///< CoupledMassState::stick_fraction
  double friction_work = 0.0;    ///< mu |C_perp| int |v| dt over the step
};

// v_new from the midpoint rule of the mass's tangential momentum (header): a v = b + J / M with
// the friction impulse J; |C_perp| from the iterate v_iterate.
CoupledRodStepper::Speed CoupledRodStepper::new_speed(const RodPointKinematics& ko, const RodPointKinematics& kn,
                                                      double v_old, double v_iterate, double dt) const {
  const Vec3 d3m = (ko.d3 + kn.d3).normalized();
  const double M = mass_.mass, hc = 0.5 * mass_.resistance * dt / M, v0 = v_old;
  const Vec3 g = model_.loads.gravity;
  const double a = kn.d3.dot(d3m) + hc;
  const double b = v0 * (ko.d3.dot(d3m) - hc) + (ko.U - kn.U).dot(d3m) + dt * (g.dot(d3m) + mass_.drive / M);
  Speed out;
  if (mass_.friction == 0.0) {
    out.v = b / a;
    return out;
  }
  const double N = normal_part(ko, v0, kn, v_iterate, d3m, M, g, dt).norm(), muN = mass_.friction * N;
  const double demand = M * g.dot(d3m) + mass_.drive - M * (kn.U - ko.U).dot(d3m) / dt;  // at sigma' = 0
  const double s = v0 != 0.0 ? sign(v0) : sign(demand), k = muN * dt / M;
  out.v = (b - s * k) / a;  // sliding along s all step
  if (s * out.v > 0.0 || (v0 == 0.0 && std::abs(demand) > muN)) {
    out.friction_work = 0.5 * muN * dt * std::abs(v0 + out.v);
    return out;
  }
  if (std::abs(demand) <= muN) {  // stops and sticks: keeps the sliding friction (the app shortens the step)
    out.stick_fraction = v0 == 0.0 ? 0.0 : v0 / (v0 - out.v);
  } else {  // reverses: J = -mu N s (2 tau - dt), tau = dt v0 / (v0 - v); a v^2 - (a v0 + b + k s) v + v0 (b - k s) = 0
    const double B = a * v0 + b + k * s, disc = std::sqrt(std::max(0.0, B * B - 4.0 * a * v0 * (b - k * s)));
    out.v = (B - s * disc) / (2.0 * a);  // the root of sign -s (the roots' product has the sign of -1)
  }
  const double tau = v0 == 0.0 ? 0.0 : dt * v0 / (v0 - out.v);
  out.friction_work = 0.5 * muN * (std::abs(v0) * tau + std::abs(out.v) * (dt - tau));
  return out;
}

CoupledStepReport CoupledRodStepper::step(RodState& state, CoupledMassState& m, double dt) {
  const StepTimes st{state.t, dt};
  Path& p = *path_;
  p.t_old = st.t_old;
  p.t_new = st.t_new();
  p.dt = dt;
  p.s_old = m.sigma;
  p.v_old = m.speed;
  if (mass_.prescribed()) {
    p.s_new = mass_.path_sigma(p.t_new);
    p.v_new = mass_.path_speed(p.t_new);
  } else {
    p.v_new = m.speed;
    p.s_new = m.sigma + dt * m.speed;
  }
  p.force = m.spring_force;
  const double ds = state.ds;
  const Vec3 g = model_.loads.gravity, up = mass_.suspension.up;
  const RodPointKinematics ko = point_kinematics(state, m.sigma, model_.props);
  p.d3 = ko.d3.normalized();
  CoupledStepReport rep;
  Speed speed;
  BodyLevel body;
  // Aitken's relaxation of the fixed point in the speed (a heavy mass) or the suspension's
  // force (a stiff spring): strong coupling
  double omega = 1.0, r_prev = 0.0;
  for (int k = 1; k <= max_coupling_iterations; ++k) {
    if (!solve_->solve(state, dt, k > 1, rep.newton_iterations)) return rep;
    const RodPointKinematics kn = solve_->point(p.s_new);
    double r = 0.0, x = 0.0;  // the fixed point's residual and variable
    if (mass_.suspended) {
      body = body_level(mass_.suspension, g, m, up.dot(kn.U + p.v_new * kn.d3), dt);
      r = body.force - p.force;
      x = p.force;
    } else if (!mass_.prescribed()) {
      speed = new_speed(ko, kn, m.speed, p.v_new, dt);
      r = speed.v - p.v_new;
      x = p.v_new;
    }
    if (!std::isfinite(r)) return rep;
    if (k > 1 && r != r_prev) omega = std::clamp(-omega * r_prev / (r - r_prev), -1e3, 1e3);
    r_prev = r;
    rep.coupling_iterations = k;
    const double previous = rep.last_change;
    if (mass_.suspended) {
      p.force = x + omega * r;
      // the body's position moves by dt^2 / (4 M_v) times the change of the force
      rep.last_change = std::abs(r) * dt * dt / (4.0 * mass_.suspension.body_mass * ds);
    } else if (!mass_.prescribed()) {
      const double v = x + omega * r;
      rep.last_change = std::abs(r) * dt / ds;  // sigma's residual is half of it
      p.s_new = m.sigma + 0.5 * dt * (m.speed + v);
      p.v_new = v;
    }
    if (air_resistance()) p.d3 = solve_->point(p.s_new).d3.normalized();  // only the point force reads it
    // converged; or at the round-off floor (a heavy mass: the change stalls a little above tol)
    if (rep.last_change <= tol || (k > 2 && rep.last_change <= 1e3 * tol && rep.last_change > 0.5 * previous)) {
      rep.converged = true;
      break;
    }
  }
  if (!rep.converged) return rep;
  // The drive is a force pair between mass and rod: its net power is D sigma'. The resistance
  // through the air acts on the mass alone: its power is c sigma' d3 . p' (p' = U + sigma' d3
  // includes the rod's material velocity along d3), here at the step's midpoint; through the
  // rod it is a pair like the drive, of power c sigma'^2. A prescribed path is kept by the
  // force along d3m that the mass's momentum balance needs: a drive of its own.
  const double vm = 0.5 * (m.speed + p.v_new);
  RodState trial = solve_->solution();
  const RodPointKinematics kn = point_kinematics(trial, p.s_new, model_.props);
  const Vec3 d3m = (ko.d3 + kn.d3).normalized();
  const Vec3 pm = 0.5 * (ko.U + m.speed * ko.d3 + kn.U + p.v_new * kn.d3);
  double drive = mass_.drive;
  if (mass_.prescribed()) {
    const Vec3 dp = (kn.U + p.v_new * kn.d3) - (ko.U + m.speed * ko.d3);
    drive = momentum_balance(mass_, dp, g, body.force, dt).dot(d3m);
  }
  m.drive_work += dt * drive * vm;
  m.dissipated += dt * mass_.resistance * vm * (mass_.resistance_through_rod ? vm : d3m.dot(pm));
  m.friction_work += speed.friction_work;
  m.stick_fraction = speed.stick_fraction;
  if (mass_.suspended) {
    m.body = body.z;
    m.body_speed = body.zt;
    m.wheel = body.w;
    m.wheel_speed = body.wt;
    m.spring_force = body.force;
    m.damper_work += body.damper_work;
  }
  m.sigma = p.s_new;
  m.speed = p.v_new;
  state = std::move(trial);
  return rep;
}

CoupledContact step_contact(const RodState& old_state, const CoupledMassState& m_old, const RodState& new_state,
                            const CoupledMassState& m_new, const CoupledRodMass& mass, const RodModel& model, double dt) {
  const Vec3& gravity = model.loads.gravity;
  const RodPointKinematics ko = point_kinematics(old_state, m_old.sigma, model.props),
                           kn = point_kinematics(new_state, m_new.sigma, model.props);
  const Vec3 d3m = (ko.d3 + kn.d3).normalized();
  const double vm = 0.5 * (m_old.speed + m_new.speed);
  const Vec3 dp = (kn.U + m_new.speed * kn.d3) - (ko.U + m_old.speed * ko.d3);
  const Vec3 C =
      momentum_balance(mass, dp, gravity, m_new.spring_force, dt) - (mass.drive - mass.resistance * vm) * d3m;
  auto d2_at = [](const RodState& s, double sigma) -> Vec3 {
    const NodeInterpolation at = locate_on_nodes(sigma, s.ds, s.num_cells());
    return (1.0 - at.xi) * s.nodes[static_cast<size_t>(at.j)].R.row(1).transpose() +
           at.xi * s.nodes[static_cast<size_t>(at.j + 1)].R.row(1).transpose();
  };
  const Vec3 d2m = (d2_at(old_state, m_old.sigma) + d2_at(new_state, m_new.sigma)).normalized();
  CoupledContact c;
  c.tangential = C.dot(d3m);
  c.normal = C - c.tangential * d3m;
  c.up = C.dot(d2m);
  return c;
}

CoupledRodEnergies coupled_energies(const RodModel& model, const RodState& state, const std::vector<Vec3>& r,
                                    const CoupledMassState& m, const CoupledRodMass& coupled) {
  const double mass = coupled.mass;
  CoupledRodEnergies e;
  e.rod = discrete_energy(state, model.props);
  const Vec3 g = model.loads.gravity;
  const double ds = state.ds;
  for (int j = 1; j <= state.num_cells(); ++j)
    e.rod_gravity -= ds * model.props.rhoA * g.dot(0.5 * (r[static_cast<size_t>(j - 1)] + r[static_cast<size_t>(j)]));
  const Vec3 pdot = mass_velocity(state, m, model.props);
  e.mass_kinetic = 0.5 * mass * pdot.squaredNorm();
  if (coupled.suspended) {
    const Vec3 across = pdot - coupled.suspension.up * coupled.suspension.up.dot(pdot);
    e.mass_kinetic += 0.5 * coupled.suspension.body_mass * across.squaredNorm();
  }
  const NodeInterpolation at = locate_on_nodes(m.sigma, ds, state.num_cells());
  const Vec3 rp = (1.0 - at.xi) * r[static_cast<size_t>(at.j)] +
                  at.xi * r[static_cast<size_t>(std::min(at.j + 1, state.num_cells()))];
  e.mass_gravity = -mass * g.dot(rp);
  e.drive_work = m.drive_work;
  e.dissipated = m.dissipated;
  e.friction_work = m.friction_work;
  if (coupled.suspended) {
    const Suspension& su = coupled.suspension;
    const double stretch = m.body - m.wheel;
    e.body = 0.5 * su.body_mass * m.body_speed * m.body_speed + 0.5 * su.stiffness * stretch * stretch -
             su.body_mass * g.dot(su.up) * m.body;
    e.damper_work = m.damper_work;
  }
  return e;
}

}  // namespace traverse::rod
