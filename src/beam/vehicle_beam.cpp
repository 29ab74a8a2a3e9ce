#include "traverse/beam/vehicle_beam.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "traverse/core/time_grid.hpp"

namespace traverse::beam {

/// Preallocated work arrays and the per-axle kinematics of the last assembly.
struct VehicleBeam::Work {
  std::vector<char> on;                 // per axle: on the beam during the current step
  std::vector<double> x, vel, acc;      // per axle at the last assembly
  MatX phi, dphi, ddphi;                // n x axles
  mutable MatX M, C, K, S;              // N x N
  mutable VecX f, r, g;                 // N
  VecX kq[4], kv[4], qs, vs;            // RK4 stages
  mutable VecX sphi, sdphi, sddphi;     // observer scratch
};

namespace {
// Positive roots tau of (a/2) tau^2 + v0 tau = target (the distance travelled equals target).
void travel_roots(double v0, double a, double target, std::vector<double>& out) {
  if (std::abs(a) < 1e-300) {
    if (v0 > 0 && target > 0) out.push_back(target / v0);
    return;
  }
  const double disc = v0 * v0 + 2.0 * a * target;
  if (disc < 0) return;
  const double q = -0.5 * (v0 + std::copysign(std::sqrt(disc), v0 == 0.0 ? 1.0 : v0));
  const double r1 = q / (0.5 * a), r2 = q != 0.0 ? -target / q : r1;
  for (const double r : {r1, r2})
    if (r > 0) out.push_back(r);
}

double lead_offset(const Vehicle& v) {
  double e = -std::numeric_limits<double>::infinity();
  for (const Axle& a : v.axles) e = std::max(e, a.offset);
  return e;
}

double entry_point(const Vehicle& v, double L) {
  if (v.motion.start) return *v.motion.start;
  return v.motion.entry == BeamEnd::Left ? 0.0 : L;
}
}  // namespace

VehicleBeam::~VehicleBeam() = default;

VehicleBeam::VehicleBeam(BeamProblem problem, std::vector<Vehicle> vehicles)
    : problem_(std::move(problem)), vehicles_(std::move(vehicles)) {
  const BeamProblem& p = problem_;
  if (!(p.length > 0) || !(p.EI > 0) || !(p.rhoA > 0))
    throw std::invalid_argument("VehicleBeam: length, EI and rhoA must be positive");
  if (!(p.dt > 0) || !(p.t_end > p.t_start)) throw std::invalid_argument("VehicleBeam: need dt > 0 and t_end > t_start");
  if (!make_time_grid(p.t_start, p.t_end, p.dt, 1e-9).ok) throw std::invalid_argument("VehicleBeam: too many steps");
  if (p.output_every < 1) throw std::invalid_argument("VehicleBeam: output_every must be >= 1");
  if (!p.loads.empty()) throw std::invalid_argument("VehicleBeam: moving loads besides the vehicles are not supported");
  if (p.adaptive) throw std::invalid_argument("VehicleBeam: adaptive steps are not supported");
  if (vehicles_.empty()) throw std::invalid_argument("VehicleBeam: no vehicle");
  modes_ = p.modes ? p.modes : std::make_shared<UniformModes>(p.support, p.n_modes, p.length, p.EI, p.rhoA);
  n_ = modes_->size();
  const std::vector<double> nodes = p.quadrature_nodes.empty()
                                        ? uniform_nodes(p.length, std::max<int>(16, 4 * static_cast<int>(n_)))
                                        : p.quadrature_nodes;
  const double EI = p.EI, rhoA = p.rhoA;
  const SectionFunction ei = p.EI_of_x ? p.EI_of_x : SectionFunction([EI](double) { return EI; });
  const SectionFunction ra = p.rhoA_of_x ? p.rhoA_of_x : SectionFunction([rhoA](double) { return rhoA; });
  mats_ = assemble_galerkin(*modes_, nodes, ra, ei, p.self_weight ? p.gravity : 0.0, p.gauss_points);
  Cb_ = modal_damping_matrix(mats_, p.damping);
  Eigen::Index row = n_;
  for (std::size_t j = 0; j < vehicles_.size(); ++j) {
    Vehicle& v = vehicles_[j];
    if (!(v.mass > 0)) throw std::invalid_argument("VehicleBeam: vehicle '" + v.name + "' needs a mass > 0");
    if (v.axles.empty()) throw std::invalid_argument("VehicleBeam: vehicle '" + v.name + "' has no axle");
    const bool pitch = v.axles.size() > 1;
    if (pitch && !(v.pitch_inertia > 0))
      throw std::invalid_argument("VehicleBeam: vehicle '" + v.name + "' has several axles: it needs a pitch inertia > 0");
    if (v.motion.speed < 0 || (v.motion.direction != 1 && v.motion.direction != -1))
      throw std::invalid_argument("VehicleBeam: vehicle '" + v.name + "': bad motion");
    for (std::size_t a = 0; a < v.axles.size(); ++a) {
      const Axle& ax = v.axles[a];
      if (!(ax.stiffness > 0) || !(ax.damping >= 0) || !(ax.wheel_mass >= 0))
        throw std::invalid_argument("VehicleBeam: vehicle '" + v.name + "': axle stiffness > 0, damping and wheel mass >= 0");
      axles_.push_back({j, a, row, pitch ? row + 1 : -1});
    }
    const auto [lo, hi] = std::minmax_element(v.axles.begin(), v.axles.end(),
                                              [](const Axle& a, const Axle& b) { return a.offset < b.offset; });
    if (pitch && lo->offset == hi->offset)
      throw std::invalid_argument("VehicleBeam: vehicle '" + v.name + "': its axles need distinct offsets (pitch)");
    row += pitch ? 2 : 1;
  }
  N_ = row;
  w_ = std::make_unique<Work>();
  Work& w = *w_;
  const std::size_t na = axles_.size();
  w.on.assign(na, 0);
  w.x.assign(na, 0.0);
  w.vel.assign(na, 0.0);
  w.acc.assign(na, 0.0);
  for (MatX* m : {&w.phi, &w.dphi, &w.ddphi}) m->setZero(n_, static_cast<Eigen::Index>(na));
  for (MatX* m : {&w.M, &w.C, &w.K, &w.S}) m->setZero(N_, N_);
  for (VecX* v : {&w.f, &w.r, &w.g, &w.qs, &w.vs}) v->setZero(N_);
  for (int s = 0; s < 4; ++s) {
    w.kq[s].setZero(N_);
    w.kv[s].setZero(N_);
  }
  for (VecX* v : {&w.sphi, &w.sdphi, &w.sddphi}) v->setZero(n_);
  q_.setZero(N_);
  v_.setZero(N_);
  a_.setZero(N_);
  reset();
}

// The leading axle's path: MovingLoad's kinematics from entry_time on, the entry speed before.
double VehicleBeam::reference_position(std::size_t j, double t) const {
  const Vehicle& v = vehicles_[j];
  const double tau = t - v.motion.entry_time;
  const double s = tau < 0 ? v.motion.speed * tau : v.motion.speed * tau + 0.5 * v.motion.acceleration * tau * tau;
  return entry_point(v, problem_.length) + v.motion.direction * s;
}
double VehicleBeam::reference_velocity(std::size_t j, double t) const {
  const Vehicle& v = vehicles_[j];
  const double tau = t - v.motion.entry_time;
  return v.motion.direction * (v.motion.speed + (tau < 0 ? 0.0 : v.motion.acceleration * tau));
}
double VehicleBeam::reference_acceleration(std::size_t j, double t) const {
  const Vehicle& v = vehicles_[j];
  return t < v.motion.entry_time ? 0.0 : v.motion.direction * v.motion.acceleration;
}

double VehicleBeam::axle_position(std::size_t j, std::size_t a) const {
  const Vehicle& v = vehicles_[j];
  return reference_position(j, t_) - v.motion.direction * (lead_offset(v) - v.axles[a].offset);
}

// Instants in (t0, t1) where an axle enters or leaves the beam, or a vehicle starts accelerating.
std::vector<double> VehicleBeam::events(double t0, double t1) const {
  std::vector<double> ev, roots;
  const double L = problem_.length;
  for (std::size_t j = 0; j < vehicles_.size(); ++j) {
    const Vehicle& v = vehicles_[j];
    const double te = v.motion.entry_time, x0 = entry_point(v, L), d = v.motion.direction;
    ev.push_back(te);
    for (const Axle& ax : v.axles) {
      const double behind = lead_offset(v) - ax.offset;
      for (const double b : {0.0, L}) {
        const double target = d * (b - x0) + behind;  // distance the lead travels from x0
        if (target < 0 && v.motion.speed > 0) ev.push_back(te + target / v.motion.speed);
        roots.clear();
        travel_roots(v.motion.speed, v.motion.acceleration, target, roots);
        if (target == 0.0) roots.push_back(0.0);
        for (const double r : roots) ev.push_back(te + r);
      }
    }
  }
  std::vector<double> in;
  for (const double t : ev)
    if (t > t0 && t < t1) in.push_back(t);
  std::sort(in.begin(), in.end());
  in.erase(std::unique(in.begin(), in.end()), in.end());
  return in;
}

void VehicleBeam::set_status(double ta, double tb) {
  const double tm = 0.5 * (ta + tb), L = problem_.length;
  for (std::size_t i = 0; i < axles_.size(); ++i) {
    const Vehicle& v = vehicles_[axles_[i].vehicle];
    const double x = reference_position(axles_[i].vehicle, tm) -
                     v.motion.direction * (lead_offset(v) - v.axles[axles_[i].axle].offset);
    w_->on[i] = x >= 0.0 && x <= L ? 1 : 0;
  }
}

// M, C, K, f of the system at time t for the current status; dynamic = false drops the terms
// of the axles' motion (the static equilibrium at rest).
void VehicleBeam::assemble(double t, bool dynamic) const {
  Work& w = *w_;
  const double g = problem_.gravity, L = problem_.length;
  w.M.setZero();
  w.C.setZero();
  w.K.setZero();
  w.f.setZero();
  w.M.topLeftCorner(n_, n_) = mats_.Mb;
  w.K.topLeftCorner(n_, n_) = mats_.Kb;
  if (Cb_.size() > 0) w.C.topLeftCorner(n_, n_) = Cb_;
  w.f.head(n_) = -mats_.Pb;
  for (std::size_t j = 0, r = static_cast<std::size_t>(n_); j < vehicles_.size(); ++j) {
    const Vehicle& v = vehicles_[j];
    const Eigen::Index z = static_cast<Eigen::Index>(r);
    w.M(z, z) = v.mass;
    w.f(z) = -v.mass * g;
    if (v.axles.size() > 1) w.M(z + 1, z + 1) = v.pitch_inertia;
    r += v.axles.size() > 1 ? 2 : 1;
  }
  for (std::size_t i = 0; i < axles_.size(); ++i) {
    const AxleRef& ar = axles_[i];
    const Vehicle& v = vehicles_[ar.vehicle];
    const Axle& ax = v.axles[ar.axle];
    const Eigen::Index k = static_cast<Eigen::Index>(i);
    const double x = reference_position(ar.vehicle, t) - v.motion.direction * (lead_offset(v) - ax.offset);
    w.x[i] = std::clamp(x, 0.0, L);
    w.vel[i] = dynamic ? reference_velocity(ar.vehicle, t) : 0.0;
    w.acc[i] = dynamic ? reference_acceleration(ar.vehicle, t) : 0.0;
    w.g.setZero();
    w.g(ar.z) = 1.0;
    if (ar.theta >= 0) w.g(ar.theta) = ax.offset;
    if (w.on[i]) {
      modes_->evaluate(w.x[i], w.phi.col(k), w.dphi.col(k), w.ddphi.col(k));
      w.g.head(n_) = -w.phi.col(k);
    }
    w.C.noalias() += (ax.damping * w.g) * w.g.transpose();
    w.K.noalias() += (ax.stiffness * w.g) * w.g.transpose();
    if (!w.on[i]) continue;
    const double vx = w.vel[i], ac = w.acc[i], mw = ax.wheel_mass;
    const auto phi = w.phi.col(k), dphi = w.dphi.col(k), ddphi = w.ddphi.col(k);
    w.K.leftCols(n_).noalias() -= (ax.damping * vx * w.g) * dphi.transpose();
    if (mw == 0.0) continue;
    w.M.topLeftCorner(n_, n_).noalias() += (mw * phi) * phi.transpose();
    w.C.topLeftCorner(n_, n_).noalias() += (2.0 * mw * vx * phi) * dphi.transpose();
    w.K.topLeftCorner(n_, n_).noalias() += (mw * phi) * (vx * vx * ddphi + ac * dphi).transpose();
    w.f.head(n_).noalias() -= (mw * g) * phi;
  }
}

void VehicleBeam::accelerations(double t, const VecX& q, const VecX& v, VecX& a) const {
  Work& w = *w_;
  assemble(t, true);
  w.r = w.f;
  w.r.noalias() -= w.C * v;
  w.r.noalias() -= w.K * q;
  a = w.M.llt().solve(w.r);
}

void VehicleBeam::rk4(double ta, double tb) {
  Work& w = *w_;
  const double h = tb - ta, tm = ta + 0.5 * h;
  w.kq[0] = v_;
  accelerations(ta, q_, v_, w.kv[0]);
  for (int s = 1; s < 4; ++s) {
    const double c = s == 3 ? h : 0.5 * h;
    w.qs = q_ + c * w.kq[s - 1];
    w.vs = v_ + c * w.kv[s - 1];
    w.kq[s] = w.vs;
    accelerations(s == 3 ? tb : tm, w.qs, w.vs, w.kv[s]);
  }
  q_ += (h / 6.0) * (w.kq[0] + 2.0 * w.kq[1] + 2.0 * w.kq[2] + w.kq[3]);
  v_ += (h / 6.0) * (w.kv[0] + 2.0 * w.kv[1] + 2.0 * w.kv[2] + w.kv[3]);
}

// Average acceleration: q1 = q0 + h v0 + h^2/4 (a0 + a1), v1 = v0 + h/2 (a0 + a1), the equation at tb.
void VehicleBeam::newmark(double ta, double tb) {
  Work& w = *w_;
  const double h = tb - ta, q = 0.25 * h * h;
  accelerations(ta, q_, v_, a_);  // with this step's status (a jumps where an axle enters)
  w.qs = q_ + h * v_ + q * a_;
  w.vs = v_ + (0.5 * h) * a_;
  assemble(tb, true);
  w.S = w.M + (0.5 * h) * w.C + q * w.K;
  w.r = w.f;
  w.r.noalias() -= w.C * w.vs;
  w.r.noalias() -= w.K * w.qs;
  const VecX a1 = w.S.partialPivLu().solve(w.r);
  q_ = w.qs + q * a1;
  v_ = w.vs + (0.5 * h) * a1;
}

void VehicleBeam::advance(double ta, double tb) {
  set_status(ta, tb);
  if (problem_.integrator == Integrator::RK4)
    rk4(ta, tb);
  else
    newmark(ta, tb);
  t_ = tb;
  ++steps_;
  refresh();
}

// The accelerations at the current state (the equation of the current status).
void VehicleBeam::refresh() { accelerations(t_, q_, v_, a_); }

void VehicleBeam::reset() {
  const BeamProblem& p = problem_;
  t_ = p.t_start;
  steps_ = 0;
  end_ = VehicleEnd::EndTime;
  events_ = events(p.t_start, p.t_end);
  double t1 = std::min(p.t_start + p.dt, p.t_end);
  const std::vector<double> ev = events(p.t_start, t1);
  if (!ev.empty()) t1 = ev.front();
  set_status(p.t_start, t1);
  q_.setZero();
  v_.setZero();
  if (p.initial_state == InitialState::Static) {
    assemble(p.t_start, false);
    q_ = w_->K.ldlt().solve(w_->f);
    // Each body moves with the ground under its axles: e' = 0 with Y' = 0, z' + e_a theta' = v w_x.
    assemble(p.t_start, true);
    for (std::size_t j = 0; j < vehicles_.size(); ++j) {
      std::vector<std::size_t> mine;
      for (std::size_t i = 0; i < axles_.size(); ++i)
        if (axles_[i].vehicle == j) mine.push_back(i);
      const bool pitch = axles_[mine[0]].theta >= 0;
      MatX A = MatX::Zero(static_cast<Eigen::Index>(mine.size()), pitch ? 2 : 1);
      VecX b = VecX::Zero(A.rows());
      for (std::size_t r = 0; r < mine.size(); ++r) {
        const std::size_t i = mine[r];
        const Eigen::Index ri = static_cast<Eigen::Index>(r);
        A(ri, 0) = 1.0;
        if (pitch) A(ri, 1) = vehicles_[j].axles[axles_[i].axle].offset;
        if (w_->on[i]) b(ri) = w_->vel[i] * w_->dphi.col(static_cast<Eigen::Index>(i)).dot(q_.head(n_));
      }
      const VecX s = A.colPivHouseholderQr().solve(b);
      v_(axles_[mine[0]].z) = s(0);
      if (pitch) v_(axles_[mine[0]].theta) = s(1);
    }
  }
  refresh();
}

double VehicleBeam::contact_force(std::size_t j, std::size_t a) const {
  std::size_t i = 0;
  while (i < axles_.size() && !(axles_[i].vehicle == j && axles_[i].axle == a)) ++i;
  if (i == axles_.size()) throw std::out_of_range("VehicleBeam::contact_force: no such axle");
  const Work& w = *w_;
  const Axle& ax = vehicles_[j].axles[a];
  const Eigen::Index k = static_cast<Eigen::Index>(i);
  double e, ed, vwx, wcdd = 0.0;
  stretch(i, e, ed, vwx);
  if (w.on[i]) {
    const auto Y = q_.head(n_), V = v_.head(n_), A = a_.head(n_);
    const double vx = w.vel[i];
    wcdd = w.phi.col(k).dot(A) + 2.0 * vx * w.dphi.col(k).dot(V) + vx * vx * w.ddphi.col(k).dot(Y) +
           w.acc[i] * w.dphi.col(k).dot(Y);
  }
  return ax.wheel_mass * (problem_.gravity + wcdd) - ax.stiffness * e - ax.damping * ed;
}

double VehicleBeam::min_contact() const {
  double m = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < axles_.size(); ++i)
    if (w_->on[i] && vehicles_[axles_[i].vehicle].unilateral)
      m = std::min(m, contact_force(axles_[i].vehicle, axles_[i].axle));
  return m;
}

// The step (ta, tb] ended with a tensile contact: shorten it to the zero of the smallest
// contact force (secant with bracketing on the step length).
bool VehicleBeam::locate_lift_off(double ta, double tb, const VecX& q0, const VecX& v0, double f0) {
  const long s0 = steps_ - 1;
  double lo = 0.0, hi = tb - ta, flo = f0, fhi;
  auto redo = [&](double h) {
    q_ = q0;
    v_ = v0;
    steps_ = s0;
    t_ = ta;
    advance(ta, ta + h);
    return min_contact();
  };
  fhi = redo(hi);
  if (!(fhi < 0.0)) return false;
  const double scale = std::abs(flo) + 1e-300;
  for (int it = 0; it < 60 && hi - lo > 1e-13 * (tb - ta); ++it) {
    double h = lo + (hi - lo) * flo / (flo - fhi);
    if (!(h > lo && h < hi)) h = 0.5 * (lo + hi);
    const double fm = redo(h);
    if (std::abs(fm) <= 1e-10 * scale) {
      hi = h;
      fhi = fm;
      break;
    }
    if (fm > 0) {
      lo = h;
      flo = fm;
    } else {
      hi = h;
      fhi = fm;
    }
  }
  redo(hi);
  return true;
}

time::Schedule VehicleBeam::schedule() const {
  time::Schedule s = beam_schedule(problem_, true);
  s.adaptive = false;  // fixed steps only
  return s;
}

double VehicleBeam::next_kink(double t) const { return time::next_after(events_, t); }

void VehicleBeam::step(double h) {
  const double ta = t_, te = t_ + h;
  const VecX q0 = q_, v0 = v_;
  const double f0 = min_contact();
  advance(ta, te);
  if (min_contact() < 0.0 && locate_lift_off(ta, te, q0, v0, f0)) end_ = VehicleEnd::LiftOff;
}

time::Attempt VehicleBeam::attempt(double) {
  throw std::logic_error("VehicleBeam: no adaptive time steps (time.adaptive)");
}

void VehicleBeam::run(const Observer& observer) {
  reset();
  if (observer) observer(*this);
  time::run_with_callback(schedule(), *this, [&] {
    if (observer) observer(*this);
  });
}

VecX VehicleBeam::Y() const { return q_.head(n_); }
VecX VehicleBeam::Ydot() const { return v_.head(n_); }
VecX VehicleBeam::Yddot() const { return a_.head(n_); }

double VehicleBeam::deflection(double x) const {
  modes_->evaluate(x, w_->sphi, w_->sdphi, w_->sddphi);
  return w_->sphi.dot(q_.head(n_));
}
double VehicleBeam::velocity(double x) const {
  modes_->evaluate(x, w_->sphi, w_->sdphi, w_->sddphi);
  return w_->sphi.dot(v_.head(n_));
}
double VehicleBeam::acceleration(double x) const {
  modes_->evaluate(x, w_->sphi, w_->sdphi, w_->sddphi);
  return w_->sphi.dot(a_.head(n_));
}

Eigen::Index VehicleBeam::body_row(std::size_t j) const {
  for (const AxleRef& a : axles_)
    if (a.vehicle == j) return a.z;
  throw std::out_of_range("VehicleBeam: no such vehicle");
}
double VehicleBeam::body_displacement(std::size_t j) const { return q_(body_row(j)); }
double VehicleBeam::body_velocity(std::size_t j) const { return v_(body_row(j)); }
double VehicleBeam::body_acceleration(std::size_t j) const { return a_(body_row(j)); }
double VehicleBeam::body_pitch(std::size_t j) const {
  return vehicles_.at(j).axles.size() > 1 ? q_(body_row(j) + 1) : 0.0;
}

// Per axle: the suspension's stretch e, its rate e' and, on the beam, v w_x at the axle.
void VehicleBeam::stretch(std::size_t i, double& e, double& ed, double& vwx) const {
  const AxleRef& ar = axles_[i];
  const Axle& ax = vehicles_[ar.vehicle].axles[ar.axle];
  const Eigen::Index k = static_cast<Eigen::Index>(i);
  e = q_(ar.z);
  ed = v_(ar.z);
  vwx = 0.0;
  if (ar.theta >= 0) {
    e += ax.offset * q_(ar.theta);
    ed += ax.offset * v_(ar.theta);
  }
  if (!w_->on[i]) return;
  vwx = w_->vel[i] * w_->dphi.col(k).dot(q_.head(n_));
  e -= w_->phi.col(k).dot(q_.head(n_));
  ed -= w_->phi.col(k).dot(v_.head(n_)) + vwx;
}

double VehicleBeam::mechanical_energy() const {
  const auto Y = q_.head(n_), V = v_.head(n_);
  double E = 0.5 * V.dot(mats_.Mb * V) + 0.5 * Y.dot(mats_.Kb * Y) + mats_.Pb.dot(Y);
  for (std::size_t j = 0; j < vehicles_.size(); ++j) {
    const Vehicle& v = vehicles_[j];
    const Eigen::Index z = body_row(j);
    E += 0.5 * v.mass * v_(z) * v_(z) + v.mass * problem_.gravity * q_(z);
    if (v.axles.size() > 1) E += 0.5 * v.pitch_inertia * v_(z + 1) * v_(z + 1);
  }
  for (std::size_t i = 0; i < axles_.size(); ++i) {
    double e, ed, vwx;
    stretch(i, e, ed, vwx);
    E += 0.5 * vehicles_[axles_[i].vehicle].axles[axles_[i].axle].stiffness * e * e;
  }
  return E;
}

double VehicleBeam::dissipation_power() const {
  const auto V = v_.head(n_);
  double P = Cb_.size() > 0 ? V.dot(Cb_ * V) : 0.0;
  for (std::size_t i = 0; i < axles_.size(); ++i) {
    double e, ed, vwx;
    stretch(i, e, ed, vwx);
    P += vehicles_[axles_[i].vehicle].axles[axles_[i].axle].damping * ed * ed;
  }
  return P;
}

double VehicleBeam::drive_power() const {
  double P = 0.0;
  for (std::size_t i = 0; i < axles_.size(); ++i) {
    const Axle& ax = vehicles_[axles_[i].vehicle].axles[axles_[i].axle];
    double e, ed, vwx;
    stretch(i, e, ed, vwx);
    P -= (ax.stiffness * e + ax.damping * ed) * vwx;
  }
  return P;
}

}  // namespace traverse::beam
