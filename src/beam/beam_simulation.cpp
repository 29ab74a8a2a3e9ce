#include "traverse/beam/beam_simulation.hpp"

#include <algorithm>
#include <string>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "traverse/core/time_grid.hpp"

namespace traverse::beam {

Section circular_tube(double E, double rho, double r_outer, double r_inner) {
  if (!(r_outer > r_inner) || r_inner < 0) throw std::invalid_argument("circular_tube: bad radii");
  const double ro2 = r_outer * r_outer, ri2 = r_inner * r_inner;
  const double A = constants::pi * (ro2 - ri2);
  const double I = 0.25 * constants::pi * (ro2 * ro2 - ri2 * ri2);
  return {E * I, rho * A};
}

/// Preallocated work arrays: nothing is allocated while stepping.
struct BeamSimulation::Work {
  Eigen::Index n = 0;
  std::size_t K = 0;
  std::vector<char> on;       // per load: acts during the current (sub)step
  std::vector<int> active;    // loads acting during the current step
  std::vector<int> massive;   // acting loads with inertia
  long epoch = 0;             // incremented whenever `on` changes
  double eval_t = std::numeric_limits<double>::quiet_NaN();
  long eval_epoch = -1;
  std::vector<double> x, v, a;  // per load at eval_t
  MatX phi, dphi, ddphi;        // n x K, column k = load k at eval_t
  MatX psi, U;                  // n x K (Woodbury)
  MatX S;                       // K x K capacitance matrix
  VecX c, beta;                 // K
  VecX r, u;                    // n
  VecX kY[4], kV[4], Ys, Vs;    // RK4 stages
  VecX Yp, Vp, A1;              // Newmark
  double h_cache[2] = {0.0, 0.0};
  MatX B_inv[2];
  int next_slot = 0;
  long A_epoch = -2;
  mutable VecX sphi, sdphi, sddphi;  // observer scratch
};

BeamSimulation::~BeamSimulation() = default;

BeamSimulation::BeamSimulation(BeamProblem problem) : problem_(std::move(problem)) {
  const BeamProblem& p = problem_;
  if (!(p.length > 0) || !(p.EI > 0) || !(p.rhoA > 0))
    throw std::invalid_argument("BeamSimulation: length, EI and rhoA must be positive");
  if (!(p.dt > 0) || !(p.t_end > p.t_start))
    throw std::invalid_argument("BeamSimulation: need dt > 0 and t_end > t_start");
  if (!make_time_grid(p.t_start, p.t_end, p.dt, kGridJoin).ok)
    throw std::invalid_argument("BeamSimulation: (t_end - t_start) / dt = " + std::to_string((p.t_end - p.t_start) / p.dt) +
                                " steps; at most 2^32 can be represented (traverse/core/time_grid.hpp)");
  if (p.output_every < 1) throw std::invalid_argument("BeamSimulation: output_every must be >= 1");
  switch (p.integrator) {
    case Integrator::RK4:
    case Integrator::Newmark:
      break;
    default:
      throw std::invalid_argument("BeamSimulation: unknown integrator");
  }
  if (p.modes) {
    modes_ = p.modes;
    if (std::abs(modes_->length() - p.length) > 1e-12 * p.length)
      throw std::invalid_argument("BeamSimulation: mode set length differs from problem length");
  } else {
    modes_ = std::make_shared<UniformModes>(p.support, p.n_modes, p.length, p.EI, p.rhoA);
  }
  const Eigen::Index n = modes_->size();
  const std::vector<double> nodes =
      p.quadrature_nodes.empty()
          ? uniform_nodes(p.length, std::max<int>(16, 4 * static_cast<int>(n)))
          : p.quadrature_nodes;
  const double EI = p.EI, rhoA = p.rhoA;
  const SectionFunction ei = p.EI_of_x ? p.EI_of_x : SectionFunction([EI](double) { return EI; });
  const SectionFunction ra =
      p.rhoA_of_x ? p.rhoA_of_x : SectionFunction([rhoA](double) { return rhoA; });
  mats_ = assemble_galerkin(*modes_, nodes, ra, ei, p.self_weight ? p.gravity : 0.0,
                            p.gauss_points);
  Mb_inv_ = mats_.Mb.ldlt().solve(MatX::Identity(n, n));
  if (p.damping.active()) C_ = modal_damping_matrix(mats_, p.damping);

  for (const MovingLoad& l : p.loads) {
    kin_.emplace_back(l, p.length);
    force_.push_back(l.vertical_force(p.gravity));
    inertia_.push_back(l.inertial_mass());
  }

  w_ = std::make_unique<Work>();
  Work& w = *w_;
  const std::size_t K = p.loads.size();
  const Eigen::Index Ki = static_cast<Eigen::Index>(K);
  w.n = n;
  w.K = K;
  w.on.assign(K, 0);
  w.active.reserve(K);
  w.massive.reserve(K);
  w.x.assign(K, 0.0);
  w.v.assign(K, 0.0);
  w.a.assign(K, 0.0);
  for (MatX* m : {&w.phi, &w.dphi, &w.ddphi, &w.psi, &w.U}) m->setZero(n, std::max<Eigen::Index>(Ki, 1));
  w.S.setZero(std::max<Eigen::Index>(Ki, 1), std::max<Eigen::Index>(Ki, 1));
  w.c.setZero(std::max<Eigen::Index>(Ki, 1));
  w.beta.setZero(std::max<Eigen::Index>(Ki, 1));
  for (VecX* v : {&w.r, &w.u, &w.Ys, &w.Vs, &w.Yp, &w.Vp, &w.A1, &w.sphi, &w.sdphi, &w.sddphi})
    v->setZero(n);
  for (int s = 0; s < 4; ++s) {
    w.kY[s].setZero(n);
    w.kV[s].setZero(n);
  }
  Y_.setZero(n);
  V_.setZero(n);
  A_.setZero(n);
  set_adaptive_floors();
  if (problem_.split_at_load_events) {
    for (const LoadKinematics& k : kin_) {
      const std::vector<double> ev = k.events(problem_.t_start, problem_.t_end);
      events_.insert(events_.end(), ev.begin(), ev.end());
    }
    std::sort(events_.begin(), events_.end());
  }
  reset();
}

// Adaptive: the floors of the relative scales (modal_scale_floors), with the loads' forces at midspan.
void BeamSimulation::set_adaptive_floors() {
  if (!problem_.adaptive) return;
  problem_.control.order = problem_.integrator == Integrator::RK4 ? 4 : 2;
  double loads = 0.0;
  for (const double f : force_) loads += std::abs(f);
  const ModalFloors f = modal_scale_floors(mats_, *modes_, problem_.length, loads);
  floor_Y_ = f.Y;
  floor_V_ = f.V;
}

void BeamSimulation::prepare_status(double ta, double tb) {
  Work& w = *w_;
  const double tm = 0.5 * (ta + tb);
  bool changed = false;
  for (std::size_t k = 0; k < w.K; ++k) {
    const char on = kin_[k].on_beam(tm) ? 1 : 0;
    if (on != w.on[k]) {
      w.on[k] = on;
      changed = true;
    }
  }
  if (!changed && w.epoch > 0) return;
  ++w.epoch;
  w.active.clear();
  w.massive.clear();
  for (std::size_t k = 0; k < w.K; ++k) {
    if (!w.on[k]) continue;
    w.active.push_back(static_cast<int>(k));
    if (inertia_[k] > 0) w.massive.push_back(static_cast<int>(k));
  }
}

void BeamSimulation::eval_loads(double t) {
  Work& w = *w_;
  if (t == w.eval_t && w.epoch == w.eval_epoch) return;
  const double L = problem_.length;
  for (int k : w.active) {
    const std::size_t ks = static_cast<std::size_t>(k);
    const double x = std::clamp(kin_[ks].position(t), 0.0, L);
    w.x[ks] = x;
    w.v[ks] = kin_[ks].velocity(t);
    w.a[ks] = kin_[ks].acceleration();
    modes_->evaluate(x, w.phi.col(k), w.dphi.col(k), w.ddphi.col(k));
  }
  w.eval_t = t;
  w.eval_epoch = w.epoch;
}

// r = -Pb - Kb Y - C V + sum_k Phi_k (F_k - M_k (2 v Phi_k'.V + v^2 Phi_k''.Y + a Phi_k'.Y))
void BeamSimulation::residual(const VecX& Y, const VecX& V, Eigen::Ref<VecX> r) const {
  const Work& w = *w_;
  r.noalias() = -mats_.Pb;
  r.noalias() -= mats_.Kb * Y;
  if (C_.size() > 0) r.noalias() -= C_ * V;
  for (int k : w.active) {
    const std::size_t ks = static_cast<std::size_t>(k);
    double f = force_[ks];
    if (inertia_[ks] > 0) {
      const double v = w.v[ks], a = w.a[ks];
      const double d1 = w.dphi.col(k).dot(Y), d1v = w.dphi.col(k).dot(V);
      const double d2 = w.ddphi.col(k).dot(Y);
      f -= inertia_[ks] * (2.0 * v * d1v + v * v * d2 + a * d1);
    }
    r.noalias() += f * w.phi.col(k);
  }
}

// out = (B + sum_j M_j phi_j psi_j^T)^{-1} r by the Woodbury identity with B^{-1} = Binv.
void BeamSimulation::solve_low_rank(const MatX& Binv, const VecX& r, VecX& out) {
  Work& w = *w_;
  w.u.noalias() = Binv * r;
  const std::size_t m = w.massive.size();
  if (m == 0) {
    out = w.u;
    return;
  }
  for (std::size_t j = 0; j < m; ++j) {
    const int k = w.massive[j];
    w.U.col(static_cast<Eigen::Index>(j)).noalias() = Binv * w.phi.col(k);
  }
  for (std::size_t i = 0; i < m; ++i) {
    const int ki = w.massive[i];
    const Eigen::Index ii = static_cast<Eigen::Index>(i);
    for (std::size_t j = 0; j < m; ++j) {
      const Eigen::Index jj = static_cast<Eigen::Index>(j);
      w.S(ii, jj) = w.psi.col(ki).dot(w.U.col(jj));
    }
    w.S(ii, ii) += 1.0 / inertia_[static_cast<std::size_t>(ki)];
    w.c(ii) = w.psi.col(ki).dot(w.u);
  }
  // Small dense solve S beta = c (Gaussian elimination with partial pivoting, in place).
  const Eigen::Index mm = static_cast<Eigen::Index>(m);
  for (Eigen::Index col = 0; col < mm; ++col) {
    Eigen::Index piv = col;
    for (Eigen::Index i = col + 1; i < mm; ++i)
      if (std::abs(w.S(i, col)) > std::abs(w.S(piv, col))) piv = i;
    if (piv != col) {
      for (Eigen::Index j = 0; j < mm; ++j) std::swap(w.S(col, j), w.S(piv, j));
      std::swap(w.c(col), w.c(piv));
    }
    for (Eigen::Index i = col + 1; i < mm; ++i) {
      const double f = w.S(i, col) / w.S(col, col);
      for (Eigen::Index j = col; j < mm; ++j) w.S(i, j) -= f * w.S(col, j);
      w.c(i) -= f * w.c(col);
    }
  }
  for (Eigen::Index i = mm - 1; i >= 0; --i) {
    double s = w.c(i);
    for (Eigen::Index j = i + 1; j < mm; ++j) s -= w.S(i, j) * w.beta(j);
    w.beta(i) = s / w.S(i, i);
  }
  out = w.u;
  for (Eigen::Index j = 0; j < mm; ++j) out.noalias() -= w.beta(j) * w.U.col(j);
}

void BeamSimulation::acceleration(double t, const VecX& Y, const VecX& V, VecX& A) {
  Work& w = *w_;
  eval_loads(t);
  residual(Y, V, w.r);
  for (int k : w.massive) w.psi.col(k) = w.phi.col(k);
  solve_low_rank(Mb_inv_, w.r, A);
}

void BeamSimulation::rk4_step(double ta, double tb) {
  Work& w = *w_;
  const double h = tb - ta, tm = ta + 0.5 * h;
  acceleration(ta, Y_, V_, w.kV[0]);
  w.kY[0] = V_;
  w.Ys = Y_ + (0.5 * h) * w.kY[0];
  w.Vs = V_ + (0.5 * h) * w.kV[0];
  acceleration(tm, w.Ys, w.Vs, w.kV[1]);
  w.kY[1] = w.Vs;
  w.Ys = Y_ + (0.5 * h) * w.kY[1];
  w.Vs = V_ + (0.5 * h) * w.kV[1];
  acceleration(tm, w.Ys, w.Vs, w.kV[2]);
  w.kY[2] = w.Vs;
  w.Ys = Y_ + h * w.kY[2];
  w.Vs = V_ + h * w.kV[2];
  acceleration(tb, w.Ys, w.Vs, w.kV[3]);
  w.kY[3] = w.Vs;
  Y_ += (h / 6.0) * (w.kY[0] + 2.0 * w.kY[1] + 2.0 * w.kY[2] + w.kY[3]);
  V_ += (h / 6.0) * (w.kV[0] + 2.0 * w.kV[1] + 2.0 * w.kV[2] + w.kV[3]);
  A_valid_ = false;
}

const MatX& BeamSimulation::newmark_inverse(double h) {
  Work& w = *w_;
  for (int s = 0; s < 2; ++s)
    if (std::abs(w.h_cache[s] - h) <= 1e-12 * h) return w.B_inv[s];
  const int s = w.next_slot;
  w.next_slot = 1 - s;
  const Eigen::Index n = w.n;
  MatX B = mats_.Mb + (0.25 * h * h) * mats_.Kb;
  if (C_.size() > 0) B += (0.5 * h) * C_;
  w.B_inv[s] = B.ldlt().solve(MatX::Identity(n, n));
  w.h_cache[s] = h;
  return w.B_inv[s];
}

void BeamSimulation::newmark_step(double ta, double tb) {
  Work& w = *w_;
  const double h = tb - ta, q = 0.25 * h * h;
  if (!A_valid_ || w.A_epoch != w.epoch) {
    // Acceleration consistent with the equation of this step's load status (it jumps when a
    // mass enters or leaves; displacement and velocity are continuous).
    acceleration(ta, Y_, V_, A_);
    A_valid_ = true;
    w.A_epoch = w.epoch;
  }
  const MatX& Binv = newmark_inverse(h);
  w.Yp = Y_ + h * V_ + q * A_;
  w.Vp = V_ + (0.5 * h) * A_;
  eval_loads(tb);
  residual(w.Yp, w.Vp, w.r);
  for (int k : w.massive) {
    const std::size_t ks = static_cast<std::size_t>(k);
    const double v = w.v[ks], a = w.a[ks];
    w.psi.col(k) = w.phi.col(k) + (h * v + q * a) * w.dphi.col(k) + (q * v * v) * w.ddphi.col(k);
  }
  solve_low_rank(Binv, w.r, w.A1);
  Y_ = w.Yp + q * w.A1;
  V_ = w.Vp + (0.5 * h) * w.A1;
  A_ = w.A1;
}

void BeamSimulation::reset() {
  const BeamProblem& p = problem_;
  Work& w = *w_;
  t_ = p.t_start;
  steps_ = 0;
  A_valid_ = false;
  totals_ = StepControlTotals();
  peak_Y_ = peak_V_ = 0.0;
  w.eval_t = std::numeric_limits<double>::quiet_NaN();
  // Status of the first (sub)step decides which loads are on the beam initially.
  double t1 = std::min(p.t_start + p.dt, p.t_end);
  for (const LoadKinematics& k : kin_) {
    const std::vector<double> ev = k.events(p.t_start, t1);
    if (!ev.empty()) t1 = std::min(t1, ev.front());
  }
  std::fill(w.on.begin(), w.on.end(), 0);
  w.epoch = 0;
  prepare_status(p.t_start, t1);
  V_.setZero();
  switch (p.initial_state) {
    case InitialState::Rest:
      Y_.setZero();
      break;
    case InitialState::Static: {
      eval_loads(p.t_start);
      VecX rhs = -mats_.Pb;
      for (int k : w.active) rhs += force_[static_cast<std::size_t>(k)] * w.phi.col(k);
      Y_ = mats_.Kb.ldlt().solve(rhs);
      break;
    }
    default:
      throw std::invalid_argument("BeamSimulation: unknown initial state");
  }
}

time::Schedule beam_schedule(const BeamProblem& p, bool split_at_kinks) {
  time::Schedule s;
  s.grid = make_time_grid(p.t_start, p.t_end, p.dt, BeamSimulation::kGridJoin).grid;
  s.every = std::max(1, p.output_every);
  s.adaptive = p.adaptive;
  s.control = p.control;
  s.split_at_kinks = split_at_kinks;
  return s;
}

time::Schedule BeamSimulation::schedule() const { return beam_schedule(problem_, problem_.split_at_load_events); }

void BeamSimulation::run(const BeamObserver& observer) {
  reset();
  if (observer) observer(snapshot());
  totals_ = time::run_with_callback(schedule(), *this, [&] {
    if (observer) observer(snapshot());
  });
}

double BeamSimulation::next_kink(double t) const { return time::next_after(events_, t); }

void BeamSimulation::step(double h) {
  advance(t_, t_ + h);
  t_ += h;
}

void BeamSimulation::advance(double ta, double tb) {
  prepare_status(ta, tb);
  if (problem_.integrator == Integrator::RK4)
    rk4_step(ta, tb);
  else
    newmark_step(ta, tb);
  ++steps_;
}

// The error of the two half steps (Yh, Vh = the current state) against the full step (Yf,
// Vf): (half - full) / (2^p - 1), weighted per group (Y, Y') by absolute + relative * scale,
// the scale the largest of the group's max-norm now, in the run so far, and its floor.
double BeamSimulation::doubling_error(const VecX& Yf, const VecX& Vf) {
  const StepControlParameters& c = problem_.control;
  const double d = std::pow(2.0, c.order) - 1.0;
  const double eY = (Y_ - Yf).lpNorm<Eigen::Infinity>() / d, eV = (V_ - Vf).lpNorm<Eigen::Infinity>() / d;
  const double sY = c.relative * std::max({Y_.lpNorm<Eigen::Infinity>(), peak_Y_, floor_Y_});
  const double sV = c.relative * std::max({V_.lpNorm<Eigen::Infinity>(), peak_V_, floor_V_});
  if (!std::isfinite(eY) || !std::isfinite(eV)) return HUGE_VAL;
  return std::max(eY > 0.0 ? eY / sY : 0.0, eV > 0.0 ? eV / sV : 0.0);
}

// One step of h against two of h / 2 from the same state; the two half steps are kept.
time::Attempt BeamSimulation::attempt(double h) {
  const double ta = t_;
  h_ = h;
  Y0_ = Y_;
  V0_ = V_;
  A0_ = A_;
  A0_valid_ = A_valid_;
  steps0_ = steps_;
  advance(ta, ta + h);
  const VecX Yf = Y_, Vf = V_;
  reject();
  advance(ta, ta + 0.5 * h);
  advance(ta + 0.5 * h, ta + h);
  time::Attempt a;
  a.converged = true;
  a.error = doubling_error(Yf, Vf);
  return a;
}

void BeamSimulation::reject() {
  Y_ = Y0_;
  V_ = V0_;
  A_ = A0_;
  A_valid_ = A0_valid_;
  steps_ = steps0_;
}

std::vector<double> BeamSimulation::accept() {
  peak_Y_ = std::max(peak_Y_, Y_.lpNorm<Eigen::Infinity>());
  peak_V_ = std::max(peak_V_, V_.lpNorm<Eigen::Infinity>());
  t_ += h_;
  return {0.5 * h_, 0.5 * h_};
}

BeamSnapshot BeamSimulation::snapshot() {
  if (!problem_.accelerations) return BeamSnapshot(*this, t_, Y_, V_, nullptr);
  // The equation of the loads' current status (that of the step just taken) at this instant.
  A_out_.resize(Y_.size());
  acceleration(t_, Y_, V_, A_out_);
  return BeamSnapshot(*this, t_, Y_, V_, &A_out_);
}

void BeamSimulation::evaluate_modes(double x) const {
  modes_->evaluate(x, w_->sphi, w_->sdphi, w_->sddphi);
}

double BeamSimulation::deflection(double x) const {
  evaluate_modes(x);
  return w_->sphi.dot(Y_);
}

double BeamSnapshot::deflection(double x) const {
  sim_->evaluate_modes(x);
  return sim_->w_->sphi.dot(Y);
}
double BeamSnapshot::slope(double x) const {
  sim_->evaluate_modes(x);
  return sim_->w_->sdphi.dot(Y);
}
double BeamSnapshot::velocity(double x) const {
  sim_->evaluate_modes(x);
  return sim_->w_->sphi.dot(Ydot);
}
double BeamSnapshot::acceleration(double x) const {
  if (!Yddot_) throw std::logic_error("BeamSnapshot::acceleration: BeamProblem::accelerations is off");
  sim_->evaluate_modes(x);
  return sim_->w_->sphi.dot(*Yddot_);
}
std::size_t BeamSnapshot::load_count() const { return sim_->kin_.size(); }
double BeamSnapshot::load_position(std::size_t k) const { return sim_->kin_.at(k).position(t); }
bool BeamSnapshot::load_on_beam(std::size_t k) const { return sim_->kin_.at(k).on_beam(t); }
double BeamSnapshot::load_deflection(std::size_t k) const {
  if (!load_on_beam(k)) return std::numeric_limits<double>::quiet_NaN();
  const double x = std::clamp(load_position(k), 0.0, sim_->problem_.length);
  return deflection(x);
}

BeamMemory beam_memory(int modes, int loads, int field_components) {
  const double m = modes;
  BeamMemory b;
  b.per_quadrature_node = 16.0;
  b.per_output_node = 8.0 + 11.0 * field_components + 3.0 * (8.0 * m + 32.0);
  b.fixed = 80.0 * m * m + 48.0 * m * loads;
  return b;
}

}  // namespace traverse::beam
