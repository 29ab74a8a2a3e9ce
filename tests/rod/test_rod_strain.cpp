// The extensible and the shearable rod (docs/rod.md, "Extensible and shearable rods") against
// closed forms: the axial step response of a clamped rod pulled at its end (a triangle wave),
// the Timoshenko frequencies of a simply supported rod, and the inextensible rod as the stiff
// limit of the same scheme.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <vector>

#include "reference_statics.hpp"
#include "reference_stepper.hpp"
#include "traverse/rod/coupled_mass_rod.hpp"
#include "rod_test_util.hpp"

namespace traverse::rod {
namespace {

constexpr double pi = constants::pi;

double order(double coarse, double fine, double ratio = 2.0) { return std::log(coarse / fine) / std::log(ratio); }

// ---------------------------------------------------------------------------------------
// Axial step: clamped at s = 0, pulled by F along k at s = L from t = 0 (a roller end sliding
// along k holds n3 = F; its lateral rows fix nothing a straight rod in pure stretch uses). The
// end moves as a triangle wave between 0 and 2 F L / (E A) with period 4 L / c, c = sqrt(E/rho).
// ---------------------------------------------------------------------------------------
struct AxialRod {
  double L = 1.0, E = 2.5e8, rho = 1500.0, radius = 0.005, F = 10.0;
  RodProperties props() const {
    RodProperties p = RodProperties::circular(radius, E, 0.25, rho);
    p.C = RodProperties::compliance(RodStrain::extensible, EA(), 0.0);
    return p;
  }
  double EA() const { return E * pi * radius * radius; }
  double c() const { return std::sqrt(E / rho); }
  double period() const { return 4.0 * L / c(); }
  /// The exact end displacement: rises at speed F c / (E A) for 2 L / c, falls back as fast.
  double end_displacement(double t) const {
    const double T = period(), x = std::fmod(t, T) / T;  // phase in [0, 1)
    const double peak = 2.0 * F * L / EA();
    return peak * (x < 0.5 ? 2.0 * x : 2.0 - 2.0 * x);
  }
};

RodModel axial_model(const AxialRod& a, int N, RodStrain strain = RodStrain::extensible) {
  RodModel m;
  m.props = a.props();
  if (strain == RodStrain::shearable) m.props.C = RodProperties::compliance(strain, a.EA(), 0.5 * a.EA());
  m.num_cells = N;
  m.length = a.L;
  m.left = EndCondition::make_clamped();
  m.right = EndCondition::make_roller(Vec3::UnitX(), Vec3::UnitZ(), a.F);
  return m;
}

/// The largest error of the end displacement (the trapezoidal integral of its velocity) at the
/// time levels over `periods` periods, at Courant number nu = c dt / ds, relative to the peak;
/// against the triangle wave delayed by `delay` steps.
double axial_step_error(const AxialRod& a, int N, double nu, double periods, double delay,
                        RodStrain strain = RodStrain::extensible) {
  const ReferenceStepper stepper(axial_model(a, N, strain));
  RodState s = straight_rest_state(N, a.L);
  const double dt = nu * (a.L / N) / a.c();
  const int steps = static_cast<int>(std::lround(periods * a.period() / dt));
  double x = 0.0, err = 0.0, u_old = 0.0;
  for (int i = 0; i < steps; ++i) {
    const ReferenceStepReport r = stepper.step(s, dt);
    EXPECT_TRUE(r.converged) << "step " << i;
    if (!r.converged) return HUGE_VAL;
    const double u = fixed_velocity(s.nodes.back()).z();
    x += 0.5 * dt * (u_old + u);
    u_old = u;
    err = std::max(err, std::abs(x - a.end_displacement(std::max(0.0, s.t - delay * dt))));
  }
  return err / (2.0 * a.F * a.L / a.EA());
}

// The scheme samples the end force at the time levels: F at level 1 and later, none at level 0.
// Its trapezoidal average over the first step is the impulse of a step at dt / 2, the time the
// box scheme reads a load that starts between two levels; the reference is the triangle wave
// delayed by dt / 2 (undelayed, the error is that delay times the end speed, first order).
//
// At Courant number 1 the box scheme carries the characteristic variables u3 -+ c C n3 exactly
// from node to node (a cell's box equation for one of them is a shift by one node per step), and
// the end conditions reflect them exactly: the end displacement is the delayed triangle wave to
// rounding, for the extensible and the shearable rod alike (a straight rod in pure stretch).
TEST(RodStrain, AxialStepIsExactAtCourantNumberOne) {
  const AxialRod a;
  for (RodStrain strain : {RodStrain::extensible, RodStrain::shearable}) {
    const double e = axial_step_error(a, 20, 1.0, 2.0, 0.5, strain);
    std::printf("%s, N = 20, c dt / ds = 1: max end displacement error / peak %.2e over two periods "
                "(peak 2 F L / (E A) = %.4e m, period 4 L / c = %.4e s)\n",
                strain == RodStrain::extensible ? "extensible" : "shearable", e, 2.0 * a.F * a.L / a.EA(),
                a.period());
    EXPECT_LT(e, 1e-9);
  }
}

// At another Courant number the step excites the scheme's dispersive waves. The end velocity
// jumps at each reflection; a second-order scheme without dissipation, whose phase error grows
// like (q ds)^2 q c t, spreads a jump into an Airy front of width ~ (c t ds^2)^(1/3), over which
// the velocity error is of the jump's size: the displacement's largest error is of that width,
// order 2/3 in ds. Asserted: the observed order between N = 40 and 80 is 2/3 within 0.1, and the
// error falls under refinement.
TEST(RodStrain, AxialStepConvergesAtCourantNumberOneHalf) {
  const AxialRod a;
  const int Ns[3] = {20, 40, 80};
  double e[3];
  for (int k = 0; k < 3; ++k) {
    e[k] = axial_step_error(a, Ns[k], 0.5, 1.0, 0.5);
    std::printf("N = %d, c dt / ds = 0.5: max end displacement error / peak %.3e over one period\n", Ns[k], e[k]);
  }
  const double p1 = order(e[0], e[1]), p2 = order(e[1], e[2]);
  std::printf("observed orders %.3f, %.3f (expected 2/3)\n", p1, p2);
  EXPECT_LT(e[2], e[1]);
  EXPECT_LT(e[1], e[0]);
  EXPECT_NEAR(p2, 2.0 / 3.0, 0.1);
}

// ---------------------------------------------------------------------------------------
// Timoshenko: a shearable rod pinned at both ends (pin axis i) vibrating in the (j, k) plane in
// mode j, wavenumber q = j pi / L. Its frequencies solve
//   (k G A q^2 - rho A w^2) (E I q^2 + k G A - rho I w^2) - (k G A q)^2 = 0,
// a quadratic in w^2 whose lower root is the bending branch.
// ---------------------------------------------------------------------------------------
struct StubbyRod {
  double L = 1.0, E = 2.5e8, nu = 0.25, rho = 1500.0, radius = 0.1;
  double k() const { return 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu); }  // Cowper, solid circle
  double A() const { return pi * radius * radius; }
  double I() const { return pi * std::pow(radius, 4) / 4.0; }
  double kGA() const { return k() * E / (2.0 * (1.0 + nu)) * A(); }
  RodProperties props() const {
    RodProperties p = RodProperties::circular(radius, E, nu, rho);
    p.C = RodProperties::compliance(RodStrain::shearable, E * A(), kGA());
    return p;
  }
  double timoshenko(int mode) const {
    const double q = mode * pi / L, rA = rho * A(), rI = rho * I(), EI = E * I();
    const double a = rA * rI, b = -(rA * (EI * q * q + kGA()) + rI * kGA() * q * q), c = kGA() * EI * std::pow(q, 4);
    return std::sqrt((-b - std::sqrt(b * b - 4.0 * a * c)) / (2.0 * a));
  }
  double euler_bernoulli(int mode) const { return std::pow(mode * pi / L, 2) * std::sqrt(E * I() / (rho * A())); }
};

/// The stubby rod pinned at both ends (pin axis i).
RodModel pinned_model(const StubbyRod& r, int N) {
  RodModel m;
  m.props = r.props();
  m.num_cells = N;
  m.length = r.L;
  m.left = m.right = EndCondition::make_pinned(Vec3::UnitX());
  return m;
}

/// Straight and unstressed, moving in the bending branch's mode `mode`: velocity
/// u2 = U sin(q s), spin omega1 = B cos(q s), B/U = w^2 rho A / (q k G A) - q (from the
/// compatibility rows). The histories hold the rates this motion has: the shear rate
/// v2_t = u2_s + omega1 (the n slot) and kappa1_t = omega1_s (with viscosity the moment and the
/// force read them); unstrained, the contact force is the viscous one, n = B_se v_t.
RodState timoshenko_mode_start(const StubbyRod& r, int N, int mode, double U, const RodProperties& p) {
  RodState s = straight_rest_state(N, r.L);
  const double q = mode * pi / r.L, w = r.timoshenko(mode), ds = r.L / N;
  const double B = (w * w * r.rho * r.A() / (q * r.kGA()) - q) * U;
  for (int j = 0; j <= N; ++j) {
    s.nodes[j].y(var::u + 1) = U * std::sin(q * j * ds);
    s.nodes[j].y(var::omega) = B * std::cos(q * j * ds);
    s.nodes[j].yt(var::n + 1) = (q * U + B) * std::cos(q * j * ds);
    s.nodes[j].yt(var::kappa) = -q * B * std::sin(q * j * ds);
    s.nodes[j].y.segment<3>(var::n) = p.B_se.cwiseProduct(s.nodes[j].yt.segment<3>(var::n));
  }
  return s;
}

/// The circular frequency of the discrete rod started in mode `mode` (timoshenko_mode_start):
/// from the zero crossings of u2 at s = L / (2 mode) over `periods` periods of
/// `steps_per_period` steps.
double measured_frequency(const StubbyRod& r, int N, int mode, double periods, int steps_per_period) {
  const ReferenceStepper stepper(pinned_model(r, N));
  RodState s = timoshenko_mode_start(r, N, mode, 1e-3, r.props());
  const double w = r.timoshenko(mode);
  const int probe = N / (2 * mode);
  const double dt = 2.0 * pi / w / steps_per_period;
  std::vector<double> crossings;
  double prev = s.nodes[probe].y(var::u + 1);
  for (int i = 0; i < static_cast<int>(periods * steps_per_period); ++i) {
    const ReferenceStepReport rep = stepper.step(s, dt);
    EXPECT_TRUE(rep.converged) << "step " << i << " its " << rep.iterations << " last dx " << rep.last_correction;
    if (!rep.converged) return 0.0;
    const double cur = s.nodes[probe].y(var::u + 1);
    if ((prev < 0.0) != (cur < 0.0)) crossings.push_back(s.t - dt * cur / (cur - prev));
    prev = cur;
  }
  if (crossings.size() < 3) return 0.0;
  const double half = (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  return pi / half;
}

// The measured frequency of mode 1 of a stubby rod (L / r = 10, where shear and rotary inertia
// lower it by several percent from Euler-Bernoulli's) approaches the Timoshenko root at second
// order in ds (the time step's error, (w dt)^2 / 24 with 1000 steps per period, is 2e-6 of it).
TEST(RodStrain, TimoshenkoFrequencyOfASimplySupportedShearableRod) {
  const StubbyRod r;
  const double wt = r.timoshenko(1), we = r.euler_bernoulli(1);
  std::printf("mode 1: Timoshenko w = %.6f rad/s, Euler-Bernoulli %.6f rad/s (%.2f %% higher)\n", wt, we,
              100.0 * (we / wt - 1.0));
  const int Ns[3] = {10, 20, 40};
  double e[3];
  for (int k = 0; k < 3; ++k) {
    const double w = measured_frequency(r, Ns[k], 1, 2.0, 1000);
    e[k] = std::abs(w / wt - 1.0);
    std::printf("N = %d: measured w = %.6f rad/s, relative error %.3e\n", Ns[k], w, e[k]);
  }
  const double p1 = order(e[0], e[1]), p2 = order(e[1], e[2]);
  std::printf("observed orders %.3f, %.3f\n", p1, p2);
  EXPECT_LT(e[1], e[0]);
  EXPECT_LT(e[2], e[1]);
  EXPECT_NEAR(p2, 2.0, 0.2);
  EXPECT_LT(e[2], 0.05 * (we / wt - 1.0));  // the shear correction is resolved
}

// A cantilever (clamped at s = 0, free at s = L) of the stubby rod: its first bending mode from
// the Timoshenko equations, solved by shooting (RK4 on 4000 steps, the frequency bisected on the
// determinant of the free end's moment and shear force):
//   w' = psi + V / kGA,  psi' = M / EI,  M' = -V - rho I w^2 psi,  V' = -rho A w^2 w,
// clamped w = psi = 0, free M = V = 0. Returns w and the shape (w(s), psi(s)) at `samples`
// equally spaced points (unit tip deflection).
struct CantileverMode {
  double w = 0.0;
  std::vector<double> deflection, rotation;
};

CantileverMode timoshenko_cantilever(const StubbyRod& r, int samples) {
  const double EI = r.E * r.I(), kGA = r.kGA(), rA = r.rho * r.A(), rI = r.rho * r.I();
  constexpr int kSteps = 4000;
  using State = std::array<double, 4>;  // w, psi, M, V
  auto rhs = [&](const State& x, double w2) {
    return State{x[1] + x[3] / kGA, x[2] / EI, -x[3] - rI * w2 * x[1], -rA * w2 * x[0]};
  };
  // Both clamped solutions to s = L (and every state along the way when `path`).
  auto shoot = [&](double w, State start, std::vector<State>* path) {
    const double h = r.L / kSteps, w2 = w * w;
    State x = start;
    if (path) path->push_back(x);
    for (int i = 0; i < kSteps; ++i) {
      auto add = [](const State& a, const State& b, double c) {
        return State{a[0] + c * b[0], a[1] + c * b[1], a[2] + c * b[2], a[3] + c * b[3]};
      };
      const State k1 = rhs(x, w2), k2 = rhs(add(x, k1, h / 2), w2), k3 = rhs(add(x, k2, h / 2), w2), k4 = rhs(add(x, k3, h), w2);
      for (int c = 0; c < 4; ++c) x[c] += h / 6.0 * (k1[c] + 2.0 * k2[c] + 2.0 * k3[c] + k4[c]);
      if (path) path->push_back(x);
    }
    return x;
  };
  auto det = [&](double w) {
    const State a = shoot(w, {0, 0, 1, 0}, nullptr), b = shoot(w, {0, 0, 0, 1}, nullptr);
    return a[2] * b[3] - a[3] * b[2];
  };
  // Euler-Bernoulli's first root (1.8751^2 sqrt(EI / rho A) / L^2) brackets from above.
  double hi = 1.8751 * 1.8751 * std::sqrt(EI / rA) / (r.L * r.L) * 1.01, lo = 0.5 * hi;
  EXPECT_LT(det(lo) * det(hi), 0.0) << "the first root is not bracketed";
  for (int i = 0; i < 200 && hi - lo > 1e-13 * hi; ++i) {
    const double mid = 0.5 * (lo + hi);
    (det(lo) * det(mid) <= 0.0 ? hi : lo) = mid;
  }
  CantileverMode m;
  m.w = 0.5 * (lo + hi);
  // The mode: the combination of the two solutions with a free end, M(L) = 0.
  const State a = shoot(m.w, {0, 0, 1, 0}, nullptr), b = shoot(m.w, {0, 0, 0, 1}, nullptr);
  const State start{0, 0, b[2], -a[2]};
  std::vector<State> path;
  shoot(m.w, start, &path);
  const double tip = path.back()[0];
  for (int k = 0; k < samples; ++k) {
    const State& x = path[static_cast<size_t>(k * kSteps / (samples - 1))];
    m.deflection.push_back(x[0] / tip);
    m.rotation.push_back(x[1] / tip);
  }
  return m;
}

// The measured frequency of the first mode of the stubby cantilever (L / r = 10) approaches the
// Timoshenko root at second order in ds. The rod starts in the mode's velocity field: u2 = U w(s),
// omega1 = -U psi(s) (the spin about d1 that turns d3 towards -j as w grows), the shear rate
// v2_t = u2_s + omega1 and kappa1_t = omega1_s in the histories; the frequency from the zero
// crossings of the tip's u2 over two periods of 1000 steps.
TEST(RodStrain, TimoshenkoFrequencyOfAShearableCantilever) {
  const StubbyRod r;
  const double EI = r.E * r.I(), we = 1.8751041 * 1.8751041 * std::sqrt(EI / (r.rho * r.A())) / (r.L * r.L);
  const int Ns[3] = {10, 20, 40};
  const CantileverMode mode = timoshenko_cantilever(r, 40 * 8 + 1);  // samples on the finest mesh's nodes / 8
  std::printf("cantilever mode 1: Timoshenko w = %.6f rad/s, Euler-Bernoulli %.6f rad/s (%.2f %% higher)\n", mode.w, we,
              100.0 * (we / mode.w - 1.0));
  double e[3];
  for (int k = 0; k < 3; ++k) {
    const int N = Ns[k], stride = 320 / N;
    RodModel m;
    m.props = r.props();
    m.num_cells = N;
    m.length = r.L;
    m.left = EndCondition::make_clamped();
    m.right = EndCondition::make_free();
    const ReferenceStepper stepper(m);
    RodState s = straight_rest_state(N, r.L);
    const double U = 1e-3, ds = r.L / N;
    auto at = [&](const std::vector<double>& f, int j) { return f[static_cast<size_t>(std::clamp(j, 0, N) * stride)]; };
    for (int j = 0; j <= N; ++j) {
      s.nodes[j].y(var::u + 1) = U * at(mode.deflection, j);
      s.nodes[j].y(var::omega) = -U * at(mode.rotation, j);
    }
    for (int j = 0; j <= N; ++j) {  // centred differences inside, one-sided at the ends
      const int a = std::max(0, j - 1), b = std::min(N, j + 1);
      const double du = (s.nodes[b].y(var::u + 1) - s.nodes[a].y(var::u + 1)) / ((b - a) * ds);
      const double dw = (s.nodes[b].y(var::omega) - s.nodes[a].y(var::omega)) / ((b - a) * ds);
      s.nodes[j].yt(var::n + 1) = du + s.nodes[j].y(var::omega);
      s.nodes[j].yt(var::kappa) = dw;
    }
    const double dt = 2.0 * pi / mode.w / 1000.0;
    std::vector<double> crossings;
    double prev = s.nodes[N].y(var::u + 1);
    for (int i = 0; i < 2000; ++i) {
      const ReferenceStepReport rep = stepper.step(s, dt);
      ASSERT_TRUE(rep.converged) << "N = " << N << " step " << i;
      const double cur = s.nodes[N].y(var::u + 1);
      if ((prev < 0.0) != (cur < 0.0)) crossings.push_back(s.t - dt * cur / (cur - prev));
      prev = cur;
    }
    ASSERT_GE(crossings.size(), 3u);
    const double w = pi * static_cast<double>(crossings.size() - 1) / (crossings.back() - crossings.front());
    e[k] = std::abs(w / mode.w - 1.0);
    std::printf("N = %d: measured w = %.6f rad/s, relative error %.3e\n", N, w, e[k]);
  }
  const double p1 = order(e[0], e[1]), p2 = order(e[1], e[2]);
  std::printf("observed orders %.3f, %.3f\n", p1, p2);
  EXPECT_NEAR(p2, 2.0, 0.3);
  EXPECT_LT(e[2], 0.05 * (we / mode.w - 1.0));  // the shear correction is resolved
}

// ---------------------------------------------------------------------------------------
// Kelvin-Voigt damping (docs/rod.md, "Material damping"): the energy balance
// d/dt (kinetic + elastic) = - integral (v_t . B_se v_t + kappa_t . B_bt kappa_t) ds, and the
// viscosities picked from a damping ratio zeta at the mode's frequency (B = 2 zeta S / w for each
// stiffness S), which make the damping proportional to the stiffness: the mode keeps its shape
// and its energy decays as exp(-2 zeta w t) over whole periods.
// ---------------------------------------------------------------------------------------
struct DampedRun {
  double balance = 0.0;   ///< |E0 - E1 - dissipated| / dissipated
  double zeta = 0.0;      ///< the damping ratio the energy's decay shows
};

/// `steps` steps of dt from `s`, E = discrete_energy, the dissipated energy the sum of dt times
/// discrete_dissipation; the decay ratio -ln(E1/E0) / (2 w t).
DampedRun damped_run(const RodModel& m, RodState s, double dt, int steps, double w) {
  const ReferenceStepper stepper(m);
  const double E0 = discrete_energy(s, m.props), t0 = s.t;
  double dissipated = 0.0;
  for (int i = 0; i < steps; ++i) {
    const RodState old = s;
    EXPECT_TRUE(stepper.step(s, dt).converged);
    dissipated += dt * discrete_dissipation(old, s, m.props);
  }
  const double E1 = discrete_energy(s, m.props);
  DampedRun out;
  out.balance = std::abs(E0 - E1 - dissipated) / dissipated;
  out.zeta = -std::log(E1 / E0) / (2.0 * w * (s.t - t0));
  std::printf("  E0 = %.6e J, E1 = %.6e J, dissipated %.6e J: balance defect %.2e, decay ratio %.5f\n", E0, E1,
              dissipated, out.balance, out.zeta);
  return out;
}

// The centred box scheme's energy identity: multiplied by the box averages of u, omega, n and m,
// the linearised cell equations sum to the change of the cell-averaged energy plus dt times the
// cell-averaged secant rates' dissipation, exactly; the rod's nonlinear terms leave a defect of
// the order of the motion's amplitude (here rotations of 1e-5). Asserted: defect below 1e-6 of
// the dissipated energy; decay ratio zeta within 1 % (the discrete mode's frequency and damping
// ratio differ from the continuous ones at O(ds^2), the damped period from the undamped one by
// zeta^2 / 2; N = 40 for the bending mode, whose shape varies along the rod).
TEST(RodStrain, KelvinVoigtDampingDissipatesAtTheRateTheoryGives) {
  const double zeta = 0.02;
  {
    const StubbyRod r;
    const double w = r.timoshenko(1), EI = r.E * r.I(), GJ = r.E / (2.0 * (1.0 + r.nu)) * 2.0 * r.I();
    RodModel m = pinned_model(r, 40);
    m.props.B_se = Vec3(kelvin_voigt_viscosity(zeta, w, r.kGA()), kelvin_voigt_viscosity(zeta, w, r.kGA()),
                        kelvin_voigt_viscosity(zeta, w, r.E * r.A()));
    m.props.B_bt = Vec3(kelvin_voigt_viscosity(zeta, w, EI), kelvin_voigt_viscosity(zeta, w, EI),
                        kelvin_voigt_viscosity(zeta, w, GJ));
    std::printf("shearable, bending mode 1 (w = %.4f rad/s), zeta = %.3f, N = 40, 400 steps per period:\n", w, zeta);
    const DampedRun d = damped_run(m, timoshenko_mode_start(r, 40, 1, 1e-3, m.props), 2.0 * pi / w / 400, 800, w);
    EXPECT_LT(d.balance, 1e-6);
    EXPECT_NEAR(d.zeta / zeta, 1.0, 0.01);
  }
  {
    // The same mode with a carried spatial history (rho_inf_space 0.8): the bending viscosity
    // reads B (kappa_s)_t, the rate of the carried kappa_s. Started from the mode's exact s-
    // derivatives (ys) and kappa_st; the undamped run shows what the scheme's own dissipation
    // in s contributes.
    const StubbyRod r;
    const int N = 40;
    const double w = r.timoshenko(1), EI = r.E * r.I(), q = pi / r.L, U = 1e-3;
    const double B = (w * w * r.rho * r.A() / (q * r.kGA()) - q) * U;
    double zetas[2] = {0.0, 0.0}, balance = 0.0;
    for (int damped = 0; damped < 2; ++damped) {
      RodModel m = pinned_model(r, N);
      m.alpha = AlphaParameters::from_rho_inf(1.0, 0.8);
      if (damped) {
        m.props.B_se = Vec3(kelvin_voigt_viscosity(zeta, w, r.kGA()), kelvin_voigt_viscosity(zeta, w, r.kGA()),
                            kelvin_voigt_viscosity(zeta, w, r.E * r.A()));
        m.props.B_bt = Vec3::Constant(kelvin_voigt_viscosity(zeta, w, EI));
      }
      RodState st = timoshenko_mode_start(r, N, 1, U, m.props);
      for (int j = 0; j <= N; ++j) {
        const double sj = j * r.L / N;
        RodNode& nd = st.nodes[j];
        nd.ys(var::u + 1) = U * q * std::cos(q * sj);
        nd.ys(var::omega) = -B * q * std::sin(q * sj);
        nd.ys(var::n + 1) = -m.props.B_se(1) * (q * U + B) * q * std::sin(q * sj);
        nd.kst(0) = -q * q * B * std::cos(q * sj);
      }
      std::printf("shearable, bending mode 1, rho_inf_space 0.8, %s:\n", damped ? "zeta = 0.02" : "undamped");
      const DampedRun d = damped_run(m, st, 2.0 * pi / w / 400, 800, w);
      zetas[damped] = d.zeta;
      if (damped) balance = d.balance;
    }
    // The carried scheme's energy identity is not exact (its spatial weights are not the
    // centred box's): the balance closes to the discretisation's order, not to round-off.
    EXPECT_LT(std::abs(zetas[0]), 0.05 * zeta);
    EXPECT_LT(balance, 1e-3);
    EXPECT_NEAR(zetas[1] / zeta, 1.0, 0.01);
  }
  {
    // Axial mode 1 of a clamped-free extensible rod, u3 = U sin(pi s / (2 L)), w = pi c / (2 L).
    const AxialRod a;
    const int N = 40;
    RodModel m = axial_model(a, N);
    m.right = EndCondition::make_free();
    const double w = pi * a.c() / (2.0 * a.L);
    m.props.B_se.z() = kelvin_voigt_viscosity(zeta, w, a.EA());
    RodState s = straight_rest_state(N, a.L);
    for (int j = 0; j <= N; ++j) {  // and its strain rate v3_t = u3_s
      s.nodes[j].y(var::u + 2) = 0.01 * std::sin(pi * j / (2.0 * N));
      s.nodes[j].yt(var::n + 2) = 0.01 * pi / (2.0 * a.L) * std::cos(pi * j / (2.0 * N));
      s.nodes[j].y(var::n + 2) = m.props.B_se.z() * s.nodes[j].yt(var::n + 2);  // unstrained: viscous force only
    }
    std::printf("extensible, axial mode 1 (w = %.4f rad/s), zeta = %.3f, N = 40, 400 steps per period:\n", w, zeta);
    const DampedRun d = damped_run(m, s, 2.0 * pi / w / 400, 800, w);
    EXPECT_LT(d.balance, 1e-6);
    EXPECT_NEAR(d.zeta / zeta, 1.0, 0.01);
  }
}

// ---------------------------------------------------------------------------------------
// Statics: the elastic catenary (Irvine). A cable of unstretched length L0 and weight
// W = rho A g L0, ends at the same height a span l apart, horizontal tension H, vertical end
// reactions V = W / 2; along the unstretched arclength s0 (z downward):
//   x(s0) = H s0 / (E A) + (H L0 / W) [asinh(V / H) - asinh((V - W s0 / L0) / H)]
//   z(s0) = (W s0 / (E A)) (V / W - s0 / (2 L0)) + (H L0 / W) [sqrt(1 + (V/H)^2) - sqrt(1 + ((V - W s0/L0)/H)^2)]
// with H from x(L0) = l. A rod with a small E I approaches it (pinned ends: no moment there).
// ---------------------------------------------------------------------------------------
struct Catenary {
  double L0 = 1.0, l = 1.0005, EA = 0.0, W = 0.0, H = 0.0;
  double x(double s0) const {
    const double V = 0.5 * W;
    return H * s0 / EA + H * L0 / W * (std::asinh(V / H) - std::asinh((V - W * s0 / L0) / H));
  }
  double z(double s0) const {
    const double V = 0.5 * W, a = V / H, b = (V - W * s0 / L0) / H;
    return W * s0 / EA * (V / W - s0 / (2.0 * L0)) + H * L0 / W * (std::sqrt(1.0 + a * a) - std::sqrt(1.0 + b * b));
  }
  /// H from x(L0) = l by bisection (x(L0) grows with H).
  void solve_tension() {
    double lo = 1e-6 * W, hi = 1e6 * W;
    for (int i = 0; i < 200; ++i) {
      H = std::sqrt(lo * hi);
      (x(L0) < l ? lo : hi) = H;
    }
  }
};

/// The discrete equilibrium of the extensible cable between pinned ends a span c.l apart under
/// gravity, N cells; the rod: radius 5 mm, E = 2.5e8 Pa, rho = 1500 kg/m^3, E I scaled by `bend`.
std::vector<StaticNode> catenary_state(int N, double bend, Catenary& c, StaticModel& m) {
  m.props = RodProperties::circular(0.005, 2.5e8, 0.25, 1500.0);
  m.props.K *= bend;
  c.EA = 2.5e8 * pi * 0.005 * 0.005;
  c.W = m.props.rhoA * 9.8 * c.L0;
  c.solve_tension();
  m.props.C = RodProperties::compliance(RodStrain::extensible, c.EA, 0.0);
  m.num_cells = N;
  m.length = c.L0;
  m.left.type = m.right.type = EndType::pinned;
  m.left.axis = m.right.axis = Vec3::UnitX();
  m.right.position = Vec3(0.0, 0.0, c.l);
  // Unloaded equilibrium: straight, stretched uniformly to the span.
  std::vector<StaticNode> nodes = straight_static_state(m);
  for (int j = 0; j <= N; ++j) {
    nodes[j].x(svar::r + 2) = c.l * j / N;
    nodes[j].x(svar::n + 2) = c.EA * (c.l / c.L0 - 1.0);
  }
  m.gravity = Vec3(0.0, -9.8, 0.0);
  const StaticReport rep = serial_load_steps(m, nodes);
  EXPECT_TRUE(rep.converged) << "N = " << N << ": " << rep.message;
  return nodes;
}

/// The largest distance of catenary_state's nodes from the catenary, relative to its sag.
double catenary_error(int N, double bend, Catenary& c) {
  StaticModel m;
  const std::vector<StaticNode> nodes = catenary_state(N, bend, c, m);
  double err = 0.0;
  for (int j = 0; j <= N; ++j) {
    const double s0 = c.L0 * j / N;
    const Vec3 exact(0.0, -c.z(s0), c.x(s0));
    err = std::max(err, (nodes[j].x.segment<3>(svar::r) - exact).norm());
  }
  return err / c.z(0.5 * c.L0);
}

// The discrete equilibrium converges to the elastic catenary at second order in ds while the
// bending stiffness's effect (a boundary layer of width sqrt(E I / H) at each end, whose
// displacement is of order the catenary's curvature times its width squared) stays below the
// discretisation error: E I of the rod / 1e4 (the layer: 0.4 mm).
TEST(RodStrain, ElasticCatenaryOfAnExtensibleCable) {
  Catenary c;
  const int Ns[3] = {20, 40, 80};
  double e[3];
  for (int k = 0; k < 3; ++k) {
    e[k] = catenary_error(Ns[k], 1e-4, c);
    std::printf("N = %d: max |r - r_catenary| / sag %.3e (H = %.4f N, sag %.4e m, strain H / (E A) = %.2e)\n", Ns[k],
                e[k], c.H, c.z(0.5 * c.L0), c.H / c.EA);
  }
  const double p1 = order(e[0], e[1]), p2 = order(e[1], e[2]);
  std::printf("observed orders %.3f, %.3f\n", p1, p2);
  EXPECT_LT(e[2], e[1]);
  EXPECT_NEAR(p2, 2.0, 0.25);
}

// The static rows are the dynamic box scheme's at rest (no strain rate, yt = 0): the static
// equilibrium of the extensible cable, as a dynamic state, stays at rest under the same loads:
// its velocities stay below what the static solve's residual test (1e-9 of the weight W per unit
// length) could accelerate in the 20 steps, 1e-9 W 20 dt / (rho A).
TEST(RodStrain, StaticEquilibriumOfAnExtensibleCableIsADynamicRest) {
  Catenary c;
  StaticModel sm;
  const std::vector<StaticNode> nodes = catenary_state(20, 1e-4, c, sm);
  RodModel m;
  m.props = sm.props;
  m.num_cells = sm.num_cells;
  m.length = sm.length;
  m.left = m.right = EndCondition::make_pinned(Vec3::UnitX());
  m.loads.gravity = sm.gravity;
  const ReferenceStepper stepper(m);
  RodState s = dynamic_state_from_static(sm, nodes);
  const double dt = 1e-3;
  double u = 0.0;
  for (int i = 0; i < 20; ++i) {
    EXPECT_TRUE(stepper.step(s, dt).converged);
    for (const RodNode& nd : s.nodes) u = std::max(u, nd.y.segment<3>(var::u).cwiseAbs().maxCoeff());
  }
  const double bound = 1e-9 * c.W * 20.0 * dt / m.props.rhoA;
  std::printf("largest velocity over 20 steps from the static state %.2e m/s (bound %.2e m/s)\n", u, bound);
  EXPECT_LT(u, bound);
}

// ---------------------------------------------------------------------------------------
// The inextensible rod is the stiff limit of the same scheme: a shearable rod whose E A and
// k G A grow by s differs from the inextensible rod by O(1/s) under the same transverse load.
// ---------------------------------------------------------------------------------------
TEST(RodStrain, StiffLimitIsTheInextensibleRod) {
  const int N = 20;
  RodModel m = test::scene_model(N);
  m.right = EndCondition::make_sliding(Vec3::UnitZ());
  m.loads.f_fixed = [](double s, double t) {
    const double p = t < 0.05 ? std::pow(std::sin(pi * t / 0.05), 4) : 0.0;
    return Vec3(0.1 * p * std::sin(2.0 * pi * s), 0.5 * p * std::sin(pi * s), 0.0);
  };
  auto run = [&](double scale) {
    RodModel mm = m;
    const double EA = 2.5e8 * pi * 0.005 * 0.005;
    if (scale > 0.0) mm.props.C = RodProperties::compliance(RodStrain::shearable, scale * EA, scale * 0.4 * EA);
    const ReferenceStepper stepper(mm);
    RodState s = straight_rest_state(N, 1.0);
    for (int i = 0; i < 50; ++i) EXPECT_TRUE(stepper.step(s, 2e-3).converged);
    VecX y(12 * (N + 1));
    for (int j = 0; j <= N; ++j) y.segment<12>(12 * j) = s.nodes[j].y;
    return y;
  };
  const VecX ref = run(0.0);
  double d[3];
  const double scales[3] = {1e2, 1e3, 1e4};
  for (int k = 0; k < 3; ++k) {
    d[k] = (run(scales[k]) - ref).cwiseAbs().maxCoeff() / ref.cwiseAbs().maxCoeff();
    std::printf("E A, k G A x %.0e: max |y - y_inextensible| / max |y| = %.3e\n", scales[k], d[k]);
  }
  const double p = order(d[1], d[2], 10.0);
  std::printf("observed order in the compliance %.3f\n", p);
  EXPECT_NEAR(p, 1.0, 0.1);
}

// The rod of the two tests below: soft (E = 2.5e6 Pa, E A = 196 N), 1 m, 50 cells, clamped at
// s = 0, a roller pulled by T = eps E A along k at s = L, no gravity; its first axial mode at
// half its critical damping (Kelvin-Voigt); at rest stretched uniformly by eps.
struct StretchedRod {
  static constexpr double L = 1.0, radius = 0.005, E = 2.5e6, rho = 1500.0, eps = 0.1;
  double EA = E * pi * radius * radius, T = eps * EA;
  RodModel model() const {
    RodModel m;
    m.props = RodProperties::circular(radius, E, 0.25, rho);
    m.props.C = RodProperties::compliance(RodStrain::extensible, EA, 0.0);
    const double w1 = pi / 2.0 * std::sqrt(E / rho) / (L * (1.0 + eps));  // clamped-free axial mode 1
    m.props.B_se = Vec3(0.0, 0.0, kelvin_voigt_viscosity(0.5, w1, EA));
    m.num_cells = 50;
    m.length = L;
    m.left = EndCondition::make_clamped();
    m.right = EndCondition::make_roller(Vec3::UnitX(), Vec3::UnitZ(), T);
    return m;
  }
  RodState start() const {
    RodState s = straight_rest_state(50, L);
    for (auto& nd : s.nodes) nd.y(var::n + 2) = T;
    return s;
  }
};

// A mass moving along a rod that strains follows the stretched centreline: its velocity is
// U + sigma' r_s, r_s = R^T v. On the straight rod stretched by the end force T (StretchedRod,
// eps = T / (E A) = 0.1), a mass accelerating
// at a in the material coordinate accelerates at a (1 + eps) in space: its inertial force on the
// rod is -M a (1 + eps) along k, and the left end's axial force settles at T - M a (1 + eps).
// The axial waves of the sudden start are damped by an axial viscosity (mode 1 at half its
// critical damping). The closed form leaves out two effects of the step of the strain the mass
// makes (M a (1 + eps) / (E A) = 0.56 %): the mass straddles it, and the rod beyond the mass
// moves as it advances; each about 0.3 % of M a (measured: 0.6 % in all, settled to 3e-4 N
// from t = 0.2 s). The tangent d3 instead of r_s would give T - M a, 10 % of M a away.
TEST(RodStrain, MovingMassFollowsTheStretchedCentreline) {
  const StretchedRod rod;
  const double eps = rod.eps, T = rod.T, M = 0.1, a = 10.0, s0 = 0.2;
  RodModel m = rod.model();
  MovingMass mm;
  mm.mass = M;
  mm.sigma = [=](double t) { return s0 + 0.5 * a * t * t; };
  mm.speed = [=](double t) { return a * t; };
  mm.accel = [=](double) { return a; };
  m.loads.masses.push_back(mm);
  RodState s = rod.start();
  const ReferenceStepper stepper(m);
  const double dt = 1e-3;
  for (int i = 0; i < 250; ++i) ASSERT_TRUE(stepper.step(s, dt).converged) << "step " << i;
  const double n0 = s.nodes.front().y(var::n + 2), expected = T - M * a * (1.0 + eps);
  std::printf("left end's axial force at t = %.3f s (sigma = %.3f m): %.6f N; T - M a (1 + eps) = %.6f N, T - M a "
              "= %.6f N (M a = %.3f N)\n", s.t, mm.sigma(s.t), n0, expected, T - M * a, M * a);
  EXPECT_NEAR(n0, expected, 0.01 * M * a);
  EXPECT_GT(std::abs(n0 - (T - M * a)), 0.05 * M * a);
}

// A coupled mass driven by D along a rod stretched by eps = 0.1 (the same rod, no gravity): its
// momentum M sigma' (1 + eps) grows at D, so it accelerates at D / (M (1 + eps)) in the
// material coordinate (D / M with the tangent d3: 10 % more). Measured once the axial waves of
// the start have died down (second difference of sigma at 0.15, 0.2, 0.25 s), to 1 %: the
// strain step D / (E A) = 0.5 % that the mass makes moves it by a fraction of that.
TEST(RodStrain, CoupledMassOnAStretchedRodMovesAlongTheStretchedCentreline) {
  const StretchedRod rod;
  const double eps = rod.eps, M = 0.1, D = 1.0, s0 = 0.2;
  const RodModel m = rod.model();
  RodState s = rod.start();
  CoupledRodMass mass;
  mass.mass = M;
  mass.drive = D;
  CoupledRodStepper stepper(m, mass, reference_rod_solve);
  CoupledMassState cm{s0, 0.0};
  const double dt = 1e-3;
  std::vector<double> at;  // sigma at t = 0.15, 0.2, 0.25 s
  for (int i = 1; i <= 250; ++i) {
    ASSERT_TRUE(stepper.step(s, cm, dt).converged) << "step " << i;
    if (i % 50 == 0 && i >= 150) at.push_back(cm.sigma);
  }
  ASSERT_EQ(at.size(), 3u);
  const double a = (at[2] - 2.0 * at[1] + at[0]) / (0.05 * 0.05), expected = D / (M * (1.0 + eps));
  std::printf("coupled mass on the stretched rod: acceleration %.6f m/s^2 (D / (M (1 + eps)) = %.6f, D / M = "
              "%.6f)\n", a, expected, D / M);
  EXPECT_NEAR(a / expected, 1.0, 0.01);
}

}  // namespace
}  // namespace traverse::rod
