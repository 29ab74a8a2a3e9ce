#include "traverse/beam/coupled_mass_beam.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "traverse/beam/beam_simulation.hpp"
#include "traverse/core/time_grid.hpp"

namespace traverse::beam {

const std::string& coupled_end_name(CoupledEnd e) {
  static const std::string names[] = {"end_time", "left_beam_at_0", "left_beam_at_L", "lift_off", "stick"};
  switch (e) {
    case CoupledEnd::EndTime:
    case CoupledEnd::LeftLeft:
    case CoupledEnd::LeftRight:
    case CoupledEnd::LiftOff:
    case CoupledEnd::Stick:
      return names[static_cast<int>(e)];
    default:
      throw std::invalid_argument("coupled_end_name: unknown end");
  }
}

/// The integrated state: modal coordinates and velocities, the mass's position and speed, and
/// the work of the drive, of the resistance and of the friction since t_start.
struct CoupledMassBeam::State {
  VecX Y, V;
  double x = 0.0, v = 0.0, drive = 0.0, loss = 0.0, friction = 0.0;
  VecX A;          ///< Y'' (Newmark only)
  double a = 0.0;  ///< x'' (Newmark only)
  double n = 0.0;  ///< the normal force N [N] (Newmark; in a derivative: N at the state)
  void resize(Eigen::Index n) {
    Y.setZero(n);
    V.setZero(n);
    A.setZero(n);
  }
  /// this = a + h b (no allocation: sizes are fixed).
  void set_axpy(const State& a, double h, const State& b) {
    Y = a.Y + h * b.Y;
    V = a.V + h * b.V;
    x = a.x + h * b.x;
    v = a.v + h * b.v;
    drive = a.drive + h * b.drive;
    loss = a.loss + h * b.loss;
    friction = a.friction + h * b.friction;
  }
  void add(double h, const State& b) {
    Y += h * b.Y;
    V += h * b.V;
    x += h * b.x;
    v += h * b.v;
    drive += h * b.drive;
    loss += h * b.loss;
    friction += h * b.friction;
  }
};

/// Scratch arrays (sized once).
struct CoupledMassBeam::Work {
  mutable VecX phi, dphi, ddphi, r0, zY, uY, A;
  State k[4], stage, s0, s1, trial;
  State mid, full;  ///< adaptive: the state after the first half step, the full step
  mutable double h_cache[2] = {0.0, 0.0};
  mutable MatX B_inv[2];  ///< (Mb + h^2/4 Kb)^{-1} for two step lengths (Newmark)
  mutable int next_slot = 0;
};

CoupledMassBeam::~CoupledMassBeam() = default;

CoupledMassBeam::CoupledMassBeam(BeamProblem problem, CoupledMass mass) : problem_(std::move(problem)), mass_(mass) {
  const BeamProblem& p = problem_;
  if (!(p.length > 0) || !(p.EI > 0) || !(p.rhoA > 0))
    throw std::invalid_argument("CoupledMassBeam: length, EI and rhoA must be positive");
  if (!(p.dt > 0) || !(p.t_end > p.t_start))
    throw std::invalid_argument("CoupledMassBeam: need dt > 0 and t_end > t_start");
  if (!make_time_grid(p.t_start, p.t_end, p.dt, 1e-9).ok)
    throw std::invalid_argument("CoupledMassBeam: too many time steps (traverse/core/time_grid.hpp)");
  if (p.output_every < 1) throw std::invalid_argument("CoupledMassBeam: output_every must be >= 1");
  if (!p.loads.empty()) throw std::invalid_argument("CoupledMassBeam: other moving loads are not supported");
  if (p.integrator != Integrator::RK4 && p.integrator != Integrator::Newmark)
    throw std::invalid_argument("CoupledMassBeam: unknown integrator");
  if (!(mass_.mass > 0) || !std::isfinite(mass_.mass)) throw std::invalid_argument("CoupledMassBeam: mass must be > 0");
  if (!(mass_.start >= 0.0 && mass_.start <= p.length))
    throw std::invalid_argument("CoupledMassBeam: start must lie on the beam, in [0, L]");
  if (!(mass_.resistance >= 0.0)) throw std::invalid_argument("CoupledMassBeam: resistance must be >= 0");
  if (!(mass_.friction >= 0.0) || !std::isfinite(mass_.friction))
    throw std::invalid_argument("CoupledMassBeam: friction must be finite and >= 0");
  modes_ = p.modes ? p.modes : std::make_shared<UniformModes>(p.support, p.n_modes, p.length, p.EI, p.rhoA);
  const Eigen::Index n = modes_->size();
  const std::vector<double> nodes = p.quadrature_nodes.empty()
                                        ? uniform_nodes(p.length, std::max<int>(16, 4 * static_cast<int>(n)))
                                        : p.quadrature_nodes;
  const double EI = p.EI, rhoA = p.rhoA;
  const SectionFunction ei = p.EI_of_x ? p.EI_of_x : SectionFunction([EI](double) { return EI; });
  const SectionFunction ra = p.rhoA_of_x ? p.rhoA_of_x : SectionFunction([rhoA](double) { return rhoA; });
  mats_ = assemble_galerkin(*modes_, nodes, ra, ei, p.self_weight ? p.gravity : 0.0, p.gauss_points);
  Mb_inv_ = mats_.Mb.ldlt().solve(MatX::Identity(n, n));
  if (problem_.adaptive) problem_.control.order = problem_.integrator == Integrator::RK4 ? 4 : 2;
  w_ = std::make_unique<Work>();
  for (VecX* v : {&w_->phi, &w_->dphi, &w_->ddphi, &w_->r0, &w_->zY, &w_->uY, &w_->A}) v->setZero(n);
  for (State* s : {&w_->k[0], &w_->k[1], &w_->k[2], &w_->k[3], &w_->stage, &w_->s0, &w_->s1, &w_->trial, &w_->mid,
                   &w_->full})
    s->resize(n);
  Y_.setZero(n);
  A_.setZero(n);
  V_.setZero(n);
  if (problem_.adaptive) set_adaptive_floors();
  reset();
}

// The rows: Binv (r0 - M Phi q) = A (beam), Mx a + M w_x q = r1 - mu s sN (n_rest + M Phi . A)
// (mass, sN the sign of N), q = Phi . A + w_x a (the mass's vertical acceleration less the
// convective terms): two scalar equations for q and a once A is eliminated.
double CoupledMassBeam::accelerations(const MatX& Binv, double Mx, double r1, double n_rest, double slope, VecX& A,
                                      double& a) const {
  const Work& w = *w_;
  const double M = mass_.mass;
  w.zY.noalias() = Binv * w.r0;
  w.uY.noalias() = Binv * w.phi;
  const double pz = w.phi.dot(w.zY), gu = w.phi.dot(w.uY);
  double N = 0.0;
  for (double side : {1.0, -1.0}) {  // N assumed positive; redone with the other sign when it is not
    const double mu = mass_.friction * dir_ * side, r1f = r1 - mu * n_rest;
    const double q = (pz + slope * (r1f - mu * M * pz) / Mx) /
                     (1.0 + M * gu + M * slope * slope / Mx - mu * M * M * gu * slope / Mx);
    A = w.zY - (M * q) * w.uY;
    const double pa = w.phi.dot(A);
    a = (r1f - M * slope * q - mu * M * pa) / Mx;
    N = n_rest + M * pa;
    if (mu == 0.0 || N * side >= 0.0) break;
  }
  return N;
}

// d = (V, A, v, a, D v, c v^2, mu |N| |v|); d.n = N.
void CoupledMassBeam::derivative(const State& s, State& d) const {
  const Work& w = *w_;
  const double M = mass_.mass, g = problem_.gravity;
  modes_->evaluate(std::clamp(s.x, 0.0, problem_.length), w.phi, w.dphi, w.ddphi);
  const double slope = w.dphi.dot(s.Y);
  const double h = 2.0 * s.v * w.dphi.dot(s.V) + s.v * s.v * w.ddphi.dot(s.Y);
  const double gh = M * (g + h), tangential = mass_.drive - mass_.resistance * s.v;
  w.r0.noalias() = -mats_.Pb;
  w.r0.noalias() -= mats_.Kb * s.Y;
  w.r0.noalias() -= gh * w.phi;
  d.n = accelerations(Mb_inv_, M, tangential - gh * slope, gh + slope * tangential, slope, d.V, d.v);
  d.Y = s.V;
  d.x = s.v;
  d.drive = mass_.drive * s.v;
  d.loss = mass_.resistance * s.v * s.v;
  d.friction = mass_.friction * std::abs(d.n * s.v);
}

void CoupledMassBeam::rk4(const State& s0, double h, State& s1) const {
  State* k = w_->k;
  State& st = w_->stage;
  derivative(s0, k[0]);
  st.set_axpy(s0, 0.5 * h, k[0]);
  derivative(st, k[1]);
  st.set_axpy(s0, 0.5 * h, k[1]);
  derivative(st, k[2]);
  st.set_axpy(s0, h, k[2]);
  derivative(st, k[3]);
  s1.set_axpy(s0, h / 6.0, k[0]);
  s1.add(h / 3.0, k[1]);
  s1.add(h / 3.0, k[2]);
  s1.add(h / 6.0, k[3]);
}

const MatX& CoupledMassBeam::newmark_inverse(double h) const {
  Work& w = *w_;
  for (int k = 0; k < 2; ++k)
    if (std::abs(w.h_cache[k] - h) <= 1e-12 * h) return w.B_inv[k];
  const int k = w.next_slot;
  w.next_slot = 1 - k;
  const MatX B = mats_.Mb + (0.25 * h * h) * mats_.Kb;
  w.B_inv[k] = B.ldlt().solve(MatX::Identity(B.rows(), B.cols()));
  w.h_cache[k] = h;
  return w.B_inv[k];
}

// Average-acceleration Newmark (the trapezoidal rule) on (Y, x) with all terms at the new level:
// Kb Y and c x' implicit through the effective matrix blockdiag(Mb + q Kb, M + c h / 2) + M G G^T
// (q = h^2/4), the modes at x and the convective terms by a fixed-point iteration on the new
// accelerations until Y and x change by less than 1e-14 of their size.
void CoupledMassBeam::newmark(const State& s0, double h, State& s1) const {
  const Work& w = *w_;
  const double q = 0.25 * h * h, M = mass_.mass, g = problem_.gravity, c = mass_.resistance;
  const MatX& Binv = newmark_inverse(h);
  const VecX Yp = s0.Y + h * s0.V + q * s0.A, Vp = s0.V + (0.5 * h) * s0.A;
  const double xp = s0.x + h * s0.v + q * s0.a, vp = s0.v + 0.5 * h * s0.a, Mx = M + 0.5 * h * c;
  s1.A = s0.A;
  s1.a = s0.a;
  for (int it = 0;; ++it) {
    if (it == 100)
      throw time::StepFailed("the Newmark iteration of the coupled mass did not converge at t = " +
                               std::to_string(t_) + " s (reduce time.dt)");
    s1.Y = Yp + q * s1.A;
    s1.V = Vp + (0.5 * h) * s1.A;
    s1.x = xp + q * s1.a;
    s1.v = vp + 0.5 * h * s1.a;
    modes_->evaluate(std::clamp(s1.x, 0.0, problem_.length), w.phi, w.dphi, w.ddphi);
    const double slope = w.dphi.dot(s1.Y);
    const double hc = 2.0 * s1.v * w.dphi.dot(s1.V) + s1.v * s1.v * w.ddphi.dot(s1.Y);
    w.r0.noalias() = -mats_.Pb;
    w.r0.noalias() -= mats_.Kb * Yp;
    w.r0.noalias() -= (M * (g + hc)) * w.phi;
    double a_new = 0.0;
    const double tangential = mass_.drive - c * s1.v;
    s1.n = accelerations(Binv, Mx, mass_.drive - c * vp - M * (g + hc) * slope, M * (g + hc) + slope * tangential, slope,
                         w.A, a_new);
    const double dY = q * (w.A - s1.A).cwiseAbs().maxCoeff(), dx = q * std::abs(a_new - s1.a);
    s1.A = w.A;
    s1.a = a_new;
    if (dx <= 1e-14 * problem_.length && dY <= 1e-14 * std::max(s1.Y.cwiseAbs().maxCoeff(), 1e-300)) break;
  }
  s1.Y = Yp + q * s1.A;
  s1.V = Vp + (0.5 * h) * s1.A;
  s1.x = xp + q * s1.a;
  s1.v = vp + 0.5 * h * s1.a;
  s1.drive = s0.drive + 0.5 * h * mass_.drive * (s0.v + s1.v);
  s1.loss = s0.loss + 0.5 * h * c * (s0.v * s0.v + s1.v * s1.v);
  s1.friction = s0.friction + 0.5 * h * mass_.friction * (std::abs(s0.n * s0.v) + std::abs(s1.n * s1.v));
}

void CoupledMassBeam::step(const State& s0, double h, State& s1) const {
  if (problem_.integrator == Integrator::Newmark)
    newmark(s0, h, s1);
  else
    rk4(s0, h, s1);
}

// >= 0 while the event has not happened: x, L - x, the normal force / (M g), x' s / sqrt(g L).
double CoupledMassBeam::event_value(CoupledEnd e, const State& s) const {
  switch (e) {
    case CoupledEnd::LeftLeft: return s.x / problem_.length;
    case CoupledEnd::LeftRight: return (problem_.length - s.x) / problem_.length;
    case CoupledEnd::LiftOff: {
      State& d = w_->k[0];
      derivative(s, d);  // leaves the modes at x in the work arrays
      const Work& w = *w_;
      const double slope = w.dphi.dot(s.Y);
      const double py = w.phi.dot(d.V) + 2.0 * s.v * w.dphi.dot(s.V) + s.v * s.v * w.ddphi.dot(s.Y) + d.v * slope;
      const double tang = mass_.mass * d.v - (mass_.drive - mass_.resistance * s.v);
      const double normal = mass_.mass * (problem_.gravity + py) - slope * tang;
      return normal / (mass_.mass * std::max(problem_.gravity, 1e-300));
    }
    case CoupledEnd::Stick: return s.v * dir_ / std::sqrt(std::max(problem_.gravity, 1e-300) * problem_.length);
    case CoupledEnd::EndTime:
    default:
      throw std::invalid_argument("CoupledMassBeam: not an event");
  }
}

// After a step s0 -> s1 of length h from t0: if an event happened in it, replaces s1 by the
// state at the earliest event (the step length found by the Illinois regula falsi on the
// event function, each trial a fresh RK4 step from s0) and returns true.
bool CoupledMassBeam::locate_event(const State& s0, double t0, double h, State& s1) {
  CoupledEnd first = CoupledEnd::EndTime;
  double tau_first = h;
  for (CoupledEnd e : {CoupledEnd::LeftLeft, CoupledEnd::LeftRight, CoupledEnd::LiftOff, CoupledEnd::Stick}) {
    if (e == CoupledEnd::LiftOff && !mass_.unilateral) continue;
    if (e == CoupledEnd::Stick && mass_.friction == 0.0) continue;
    const double gb0 = event_value(e, s1);
    if (!(gb0 < 0.0)) continue;
    double a = 0.0, b = h, ga = event_value(e, s0), gb = gb0;
    if (e == CoupledEnd::Stick && !(ga > 0.0)) continue;  // just reversed: x' s starts at 0
    if (!(ga > 0.0)) b = 0.0;  // at the event already (e.g. at an end, moving off)
    int side = 0;
    for (int it = 0; it < 100 && b - a > 1e-14 * h; ++it) {
      const double c = ga > 0.0 ? (a * gb - b * ga) / (gb - ga) : a;
      if (c <= a || c >= b) break;
      advance(s0, c, w_->trial);
      const double gc = event_value(e, w_->trial);
      if (std::abs(gc) < 1e-15) {
        b = c;
        break;
      }
      if (gc > 0.0) {
        a = c;
        ga = gc;
        if (side == -1) gb *= 0.5;
        side = -1;
      } else {
        b = c;
        gb = gc;
        if (side == +1) ga *= 0.5;
        side = +1;
      }
    }
    if (b < tau_first || first == CoupledEnd::EndTime) {
      tau_first = b;
      first = e;
    }
  }
  if (first == CoupledEnd::EndTime) return false;
  if (tau_first < h) advance(s0, tau_first, s1);
  end_ = first;
  t_ = t0 + tau_first;
  return true;
}

void CoupledMassBeam::load_state(const State& s) {
  Y_ = s.Y;
  V_ = s.V;
  x_ = s.x;
  v_ = s.v;
  work_drive_ = s.drive;
  work_loss_ = s.loss;
  work_friction_ = s.friction;
  A_ = s.A;
  a_ = s.a;
  n_ = s.n;
}

// At x' = 0 (h = 0), the mass held at its material point: (Mb + M Phi Phi^T) Y'' = -Pb - Kb Y -
// M g Phi, q = Phi . Y''; the friction force that holds it F = M w_x (g + q) - D, against mu |N|,
// N = M (g + q) + w_x D. `direction`: where it slides when F is too large (the sign of -F).
bool CoupledMassBeam::holds(const State& s, double& direction) const {
  const Work& w = *w_;
  const double M = mass_.mass, g = problem_.gravity;
  modes_->evaluate(std::clamp(s.x, 0.0, problem_.length), w.phi, w.dphi, w.ddphi);
  const double slope = w.dphi.dot(s.Y);
  w.r0.noalias() = -mats_.Pb;
  w.r0.noalias() -= mats_.Kb * s.Y;
  w.r0.noalias() -= (M * g) * w.phi;
  w.zY.noalias() = Mb_inv_ * w.r0;
  w.uY.noalias() = Mb_inv_ * w.phi;
  const double q = w.phi.dot(w.zY) / (1.0 + M * w.phi.dot(w.uY));
  const double F = M * slope * (g + q) - mass_.drive, N = M * (g + q) + slope * mass_.drive;
  direction = F > 0.0 ? -1.0 : 1.0;
  return std::abs(F) <= mass_.friction * std::abs(N);
}

void CoupledMassBeam::refresh_accelerations() {
  const State d = current_derivative();
  A_ = d.V;
  a_ = d.v;
  n_ = d.n;
}

void CoupledMassBeam::reset() {
  const BeamProblem& p = problem_;
  t_ = p.t_start;
  steps_ = 0;
  end_ = CoupledEnd::EndTime;
  x_ = mass_.start;
  v_ = mass_.velocity;
  work_drive_ = work_loss_ = work_friction_ = 0.0;
  V_.setZero();
  switch (p.initial_state) {
    case InitialState::Rest: Y_.setZero(); break;
    case InitialState::Static: {
      Work& w = *w_;
      modes_->evaluate(x_, w.phi, w.dphi, w.ddphi);
      const VecX rhs = -mats_.Pb - mass_.mass * p.gravity * w.phi;
      Y_ = mats_.Kb.ldlt().solve(rhs);
      break;
    }
    default: throw std::invalid_argument("CoupledMassBeam: unknown initial state");
  }
  totals_ = StepControlTotals();
  peak_Y_ = peak_V_ = peak_dx_ = peak_v_ = 0.0;
  dir_ = v_ < 0.0 ? -1.0 : 1.0;
  if (mass_.friction > 0.0 && v_ == 0.0) {  // from rest: stuck, or sliding where the forces push it
    State s;
    s.Y = Y_;
    s.x = x_;
    if (holds(s, dir_)) end_ = CoupledEnd::Stick;
  }
  refresh_accelerations();
}

void CoupledMassBeam::advance(const State& s0, double h, State& s1) const {
  if (!problem_.adaptive) {
    step(s0, h, s1);
    return;
  }
  step(s0, 0.5 * h, w_->mid);
  step(w_->mid, 0.5 * h, s1);
}

// Adaptive: the floors of the groups' scales: the modal ones (modal_scale_floors) with the
// mass's weight at midspan; 1e-3 of the beam's length for the mass's travel x - x(t_start),
// times the first modal frequency (V's floor over Y's) for its speed x'.
void CoupledMassBeam::set_adaptive_floors() {
  const ModalFloors f = modal_scale_floors(mats_, *modes_, problem_.length, mass_.mass * problem_.gravity);
  floor_Y_ = f.Y;
  floor_V_ = f.V;
  floor_x_ = 1e-3 * problem_.length;
  floor_v_ = floor_x_ * std::sqrt(mats_.Kb(0, 0) / mats_.Mb(0, 0));
}

double CoupledMassBeam::doubling_error(const State& half, const State& full) const {
  const StepControlParameters& c = problem_.control;
  const double d = std::pow(2.0, c.order) - 1.0;
  const double e[4] = {(half.Y - full.Y).lpNorm<Eigen::Infinity>() / d, (half.V - full.V).lpNorm<Eigen::Infinity>() / d,
                       std::abs(half.x - full.x) / d, std::abs(half.v - full.v) / d};
  const double scale[4] = {std::max({half.Y.lpNorm<Eigen::Infinity>(), peak_Y_, floor_Y_}),
                           std::max({half.V.lpNorm<Eigen::Infinity>(), peak_V_, floor_V_}),
                           std::max({std::abs(half.x - mass_.start), peak_dx_, floor_x_}),
                           std::max({std::abs(half.v), peak_v_, floor_v_})};
  double err = 0.0;
  for (int g = 0; g < 4; ++g) {
    if (!std::isfinite(e[g])) return HUGE_VAL;
    err = std::max(err, e[g] / (c.relative * scale[g]));
  }
  return err;
}

// One step of h checked by step doubling: the full step against the two half steps kept.
time::Attempt CoupledMassBeam::attempt(double h) {
  Work& w = *w_;
  time::Attempt a;
  h_ = h;
  current_state(w.s0);
  try {
    step(w.s0, h, w.full);
    advance(w.s0, h, w.s1);
  } catch (const time::StepFailed& e) {  // the Newmark iteration did not converge
    a.why = std::string("the step failed (") + e.what() + ")";
    return a;
  }
  a.converged = true;
  a.error = doubling_error(w.s1, w.full);
  return a;
}

// The accepted attempt becomes the state; an event in it (located by the same pair of half
// steps) shortens it: the run ends there, or the mass reverses at a stop and the run goes on.
std::vector<double> CoupledMassBeam::accept() {
  Work& w = *w_;
  const double t0 = t_;
  const bool event = locate_event(w.s0, t0, h_, w.s1);  // on an event: t_ at it, the step shortened
  load_state(w.s1);
  const double taken = event ? t_ - t0 : h_;
  std::vector<double> lengths;
  if (taken > 0.0) {
    lengths = {0.5 * taken, 0.5 * taken};
    steps_ += 2;
  }
  peak_Y_ = std::max(peak_Y_, Y_.lpNorm<Eigen::Infinity>());
  peak_V_ = std::max(peak_V_, V_.lpNorm<Eigen::Infinity>());
  peak_dx_ = std::max(peak_dx_, std::abs(x_ - mass_.start));
  peak_v_ = std::max(peak_v_, std::abs(v_));
  if (!event) {
    t_ = t0 + h_;
  } else if (end_ == CoupledEnd::Stick && !holds(w.s1, dir_)) {
    end_ = CoupledEnd::EndTime;  // x' = 0 with the demand above mu |N|: reverses (dir_ flipped by holds)
    refresh_accelerations();
  }
  return lengths;
}

void CoupledMassBeam::current_state(State& s) const {
  s.Y = Y_;
  s.V = V_;
  s.x = x_;
  s.v = v_;
  s.drive = work_drive_;
  s.loss = work_loss_;
  s.friction = work_friction_;
  s.A = A_;
  s.a = a_;
  s.n = n_;
}

// One grid step from t_ to t_target, split where the friction reverses the mass; true at an
// event that ends the run (the state and t_ there).
bool CoupledMassBeam::advance_to(double t_target) {
  Work& w = *w_;
  ++steps_;
  for (int part = 0; part < 100; ++part) {
    const double t0 = t_, h = t_target - t0;
    if (h <= 1e-12 * problem_.dt) break;  // reversed at the step's end
    current_state(w.s0);
    step(w.s0, h, w.s1);
    const bool event = locate_event(w.s0, t0, h, w.s1);
    load_state(w.s1);
    if (!event) break;
    if (end_ != CoupledEnd::Stick || holds(w.s1, dir_)) return true;
    end_ = CoupledEnd::EndTime;  // x' = 0 with the demand above mu |N|: reverses (dir_ flipped by holds)
    refresh_accelerations();
  }
  t_ = t_target;
  return false;
}

time::Schedule CoupledMassBeam::schedule() const { return beam_schedule(problem_, false); }

void CoupledMassBeam::step(double h) { advance_to(t_ + h); }

void CoupledMassBeam::run(const Observer& observer) {
  reset();
  if (observer) observer(*this);
  totals_ = time::run_with_callback(schedule(), *this, [&] {  // stuck at the start: no step
    if (observer) observer(*this);
  });
}

CoupledMassBeam::State CoupledMassBeam::current_derivative() const {
  State s;
  s.Y = Y_;
  s.V = V_;
  s.x = x_;
  s.v = v_;
  State d;
  d.resize(Y_.size());
  derivative(s, d);
  return d;
}

double CoupledMassBeam::acceleration() const { return current_derivative().v; }

double CoupledMassBeam::vertical_acceleration() const {
  const State d = current_derivative();
  const Work& w = *w_;
  return w.phi.dot(d.V) + 2.0 * v_ * w.dphi.dot(V_) + v_ * v_ * w.ddphi.dot(Y_) + d.v * w.dphi.dot(Y_);
}

double CoupledMassBeam::deflection(double x) const {
  modes_->evaluate(x, w_->phi, w_->dphi, w_->ddphi);
  return w_->phi.dot(Y_);
}
double CoupledMassBeam::velocity(double x) const {
  modes_->evaluate(x, w_->phi, w_->dphi, w_->ddphi);
  return w_->phi.dot(V_);
}
double CoupledMassBeam::slope(double x) const {
  modes_->evaluate(x, w_->phi, w_->dphi, w_->ddphi);
  return w_->dphi.dot(Y_);
}
double CoupledMassBeam::mass_vertical_velocity() const {
  const double xc = std::clamp(x_, 0.0, problem_.length);
  return velocity(xc) + v_ * slope(xc);
}

double CoupledMassBeam::normal_force() const {
  const double a = acceleration(), py = vertical_acceleration();
  const double s = slope(std::clamp(x_, 0.0, problem_.length));
  const double tang = mass_.mass * a - (mass_.drive - mass_.resistance * v_);
  return (mass_.mass * (problem_.gravity + py) - s * tang) / std::sqrt(1.0 + s * s);
}

double CoupledMassBeam::tangential_force() const {
  const double a = acceleration(), py = vertical_acceleration();
  const double s = slope(std::clamp(x_, 0.0, problem_.length));
  const double tang = mass_.mass * a - (mass_.drive - mass_.resistance * v_);
  return (tang + s * mass_.mass * (problem_.gravity + py)) / std::sqrt(1.0 + s * s);
}

CoupledEnergies CoupledMassBeam::energies() const {
  CoupledEnergies e;
  e.beam_kinetic = 0.5 * V_.dot(mats_.Mb * V_);
  e.beam_elastic = 0.5 * Y_.dot(mats_.Kb * Y_);
  e.beam_gravity = mats_.Pb.dot(Y_);
  const double wdot = mass_vertical_velocity();
  e.mass_kinetic = 0.5 * mass_.mass * (v_ * v_ + wdot * wdot);
  e.mass_gravity = mass_.mass * problem_.gravity * deflection(std::clamp(x_, 0.0, problem_.length));
  e.drive_work = work_drive_;
  e.dissipated = work_loss_;
  e.friction_work = work_friction_;
  return e;
}

}  // namespace traverse::beam
