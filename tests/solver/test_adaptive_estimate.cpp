// The adaptive step's error estimate (rod/time_error.hpp, docs/adaptive.md) on the rod itself:
// a cantilever (scene rod, 20 cells, clamped / free, no gravity) at rest under a point force at
// s = 0.7 m that grows smoothly from zero (0.05 N (1 - cos(pi t / 0.2 s)) / 2: a smooth
// forcing, so that the local error is the scheme's, not that of grid-scale waves a sudden
// load would excite), stepped with the distributed stepper at a fixed h to t = 0.05 s; then one step of h against 64 steps
// of h / 64 from the same state (the reference; its own error is 4096 times smaller). The
// estimate of the position group (the trapezoidal displacement error) and of the u group
// (the extrapolation estimate) must follow the true local error in order and constant.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rod_mpi_test_util.hpp"
#include "traverse/rod/time_error.hpp"

namespace traverse::solver {
namespace {

using test::say;

std::vector<rod::NodeLevel> levels(const DistributedStepper& st) {
  std::vector<rod::NodeLevel> y;
  for (int k = 0; k < st.num_owned_nodes(); ++k) y.push_back(rod::node_level(st.owned_node(k)));
  return y;
}

struct Measured {
  double est_disp = 0, true_disp = 0, est_u = 0, true_u = 0;
};

double global_max(double v) {
  double out = v;
  Teuchos::reduceAll<int, double>(*test::comm(), Teuchos::REDUCE_MAX, 1, &v, &out);
  return out;
}

Measured measure(double h) {
  Teuchos::ParameterList params = test::solver_params("auto");
  params.set("Residual Tolerance", 1e-11);
  rod::RodModel model = test::cantilever(20, false);
  model.loads.gravity = Vec3::Zero();
  model.loads.point_forces.push_back({[](double t) {
                                        const double r = t < 0.2 ? 0.5 * (1.0 - std::cos(M_PI * t / 0.2)) : 1.0;
                                        return Vec3(0.0, -0.05 * r, 0.0);
                                      },
                                      [](double) { return 0.7; }});
  DistributedStepper st(model, test::comm(), params);
  rod::LevelHistory hist;
  hist.start(levels(st));
  const int steps = static_cast<int>(std::lround(0.05 / h));
  for (int i = 0; i < steps; ++i) {
    st.step(h);
    hist.push(levels(st), h);
  }
  const rod::RodState start = st.ghosted_piece();
  const std::vector<rod::NodeLevel> y0 = levels(st);
  st.step(h);
  const std::vector<rod::NodeLevel> y1 = levels(st);
  const rod::TimeErrorParts est = rod::extrapolation_error(y1, hist, h, 1.0 / 12.0);
  // Reference: 64 steps of h / 64, the displacement summed by the same trapezoidal rule.
  st.set_state(start, st.first_ghosted_node());
  std::vector<Vec3> d(y0.size(), Vec3::Zero());
  std::vector<rod::NodeLevel> prev = y0;
  for (int i = 0; i < 64; ++i) {
    st.step(h / 64.0);
    const std::vector<rod::NodeLevel> y = levels(st);
    for (size_t j = 0; j < y.size(); ++j) d[j] += h / 128.0 * (prev[j].head<3>() + y[j].head<3>());
    prev = y;
  }
  Measured m;
  for (size_t j = 0; j < y1.size(); ++j) {
    const Vec3 d1 = 0.5 * h * (y0[j].head<3>() + y1[j].head<3>());
    m.true_disp = std::max(m.true_disp, (d1 - d[j]).norm());
    m.true_u = std::max(m.true_u, (y1[j].segment<3>(6) - prev[j].segment<3>(6)).norm());
  }
  m.true_disp = global_max(m.true_disp);
  m.true_u = global_max(m.true_u);
  m.est_disp = global_max(est.error[0]);
  m.est_u = global_max(est.error[2]);
  return m;
}

TEST(AdaptiveEstimate, FollowsTheRodsTrueLocalError) {
  std::vector<Measured> ms;
  for (const double h : {4e-3, 2e-3, 1e-3}) {
    ms.push_back(measure(h));
    const Measured& m = ms.back();
    say("  h = %.0e s: displacement est %.4e true %.4e m (ratio %.3f); u est %.4e true %.4e m/s (ratio %.3f)\n", h,
        m.est_disp, m.true_disp, m.est_disp / m.true_disp, m.est_u, m.true_u, m.est_u / m.true_u);
  }
  for (size_t i = 1; i < ms.size(); ++i) {
    const double od = std::log2(ms[i - 1].est_disp / ms[i].est_disp), td = std::log2(ms[i - 1].true_disp / ms[i].true_disp);
    const double ou = std::log2(ms[i - 1].est_u / ms[i].est_u), tu = std::log2(ms[i - 1].true_u / ms[i].true_u);
    say("  orders: displacement est %.3f true %.3f; u est %.3f true %.3f\n", od, td, ou, tu);
    EXPECT_NEAR(od, 3.0, 0.2);
    EXPECT_NEAR(td, 3.0, 0.2);
    // u's true local error converges at order 2.5-2.8 here (the 20-cell grid's stiff modes,
    // h omega up to about 4 at h = 4 ms); the estimate follows it within 0.4.
    EXPECT_NEAR(ou, tu, 0.4);
  }
  EXPECT_NEAR(ms.back().est_disp / ms.back().true_disp, 1.0, 0.05);
  EXPECT_NEAR(ms.back().est_u / ms.back().true_u, 1.0, 0.25);
}

}  // namespace
}  // namespace traverse::solver
