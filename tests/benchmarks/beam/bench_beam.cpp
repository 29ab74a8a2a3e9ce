// Benchmark (not a test): run time against tip-deflection error for the cantilever launch
// barrel scene (spec: p = 20 %, v = 100 m/s), over the time step and the number of modes,
// for RK4 and Newmark. Error = max over t in [0, L/v] (every 1e-4 s) of |w(L, t) - w_ref(L, t)|
// with w_ref from RK4, 30 modes, dt = 1e-7 s.
#include <chrono>
#include <cmath>
#include <cstdio>
#include <vector>

#include "traverse/beam/beam_simulation.hpp"

using namespace traverse;
using namespace traverse::beam;

namespace {
constexpr double kEvery = 1e-4;  // comparison grid [s]

BeamProblem scene(Integrator integ, int n, double dt) {
  const Section s = circular_tube(2.0e11, 7850, 0.1, 0.05);
  BeamProblem p;
  p.length = 2.0;
  p.EI = s.EI;
  p.rhoA = s.rhoA;
  p.support = Support::ClampedFree;
  p.n_modes = n;
  p.gravity = 9.8;
  const double pm = 0.2, mb = s.rhoA * p.length;
  MovingLoad m;
  m.kind = LoadKind::Mass;
  m.mass = pm / (1 - pm) * mb;
  m.entry = BeamEnd::Left;
  m.speed = 100.0;
  p.loads.push_back(m);
  p.t_end = p.length / m.speed;
  p.dt = dt;
  p.output_every = static_cast<int>(std::lround(kEvery / dt));
  p.integrator = integ;
  return p;
}

std::vector<double> tip(const BeamProblem& p, double* seconds) {
  std::vector<double> out;
  int reps = 0;
  const auto t0 = std::chrono::steady_clock::now();
  double el = 0;
  do {
    out.clear();
    BeamSimulation sim(p);
    sim.run([&](const BeamSnapshot& s) { out.push_back(s.deflection(p.length)); });
    ++reps;
    el = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } while (el < 0.2 && reps < 1000);
  if (seconds) *seconds = el / reps;
  return out;
}
}  // namespace

int main() {
  double tref = 0;
  const std::vector<double> ref = tip(scene(Integrator::RK4, 30, 1e-7), &tref);
  double scale = 0;
  for (double w : ref) scale = std::max(scale, std::abs(w));
  std::printf("Cantilever launch barrel, p = 20 %%, v = 100 m/s, t in [0, %.3f] s\n", 0.02);
  std::printf("reference: RK4, 30 modes, dt = 1e-7 s (%.3f s); max |w_tip| = %.6e m\n\n", tref, scale);
  std::printf("| method  | modes | dt [s]  | steps  | time/run [ms] | max tip error [m] | rel. error |\n");
  std::printf("|---------|------:|--------:|-------:|--------------:|------------------:|-----------:|\n");
  const double dts[] = {1e-4, 5e-5, 2e-5, 1e-5, 5e-6, 2e-6, 1e-6};
  for (Integrator integ : {Integrator::RK4, Integrator::Newmark}) {
    for (int n : {3, 5, 10, 20, 30}) {
      for (double dt : dts) {
        const BeamProblem p = scene(integ, n, dt);
        double sec = 0;
        const std::vector<double> w = tip(p, &sec);
        double e = 0;
        bool bad = w.size() != ref.size();
        for (std::size_t i = 0; i < std::min(w.size(), ref.size()); ++i) {
          if (!std::isfinite(w[i])) bad = true;
          e = std::max(e, std::abs(w[i] - ref[i]));
        }
        const char* name = integ == Integrator::RK4 ? "RK4" : "Newmark";
        const long steps = std::lround(p.t_end / dt);
        if (bad || e > 1.0)
          std::printf("| %-7s | %5d | %7.0e | %6ld | %13.3f | %17s | %10s |\n", name, n, dt, steps, sec * 1e3,
                      "unstable", "-");
        else
          std::printf("| %-7s | %5d | %7.0e | %6ld | %13.3f | %17.3e | %10.2e |\n", name, n, dt, steps, sec * 1e3,
                      e, e / scale);
      }
    }
  }
  return 0;
}
