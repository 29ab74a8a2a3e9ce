// Statics through LOCA on the distributed static model: Euler buckling as a pitchfork (order 2
// in ds), the buckled pinned-pinned elastica against its closed form, Greenhill's heavy column
// as a pitchfork in the gravity factor. Runs on 1 and 2 ranks; the distributed answers are
// compared with the serial sparse-LU reference (reference_statics.hpp) to 1e-8, so both rank
// counts give the same answers.
#include <gtest/gtest.h>

#include <Tpetra_Core.hpp>
#include <cmath>
#include <cstdio>

#include "statics_test_util.hpp"
#include "traverse/core/so3.hpp"
#include "reference_statics.hpp"
#include "traverse/rod/static_load_steps.hpp"
#include "traverse/solver/static_continuation.hpp"

using namespace traverse;
using rod::StaticParameter;

namespace {

solver::Comm comm() { return Tpetra::getDefaultComm(); }
bool root() { return comm()->getRank() == 0; }

// Complete elliptic integrals K(k), E(k) by the arithmetic-geometric mean.
void elliptic(double k, double& K, double& E) {
  double a = 1.0, b = std::sqrt(1.0 - k * k), c = k, sum = 0.5 * c * c, pow2 = 0.5;
  while (std::abs(c) > 1e-16) {
    const double an = 0.5 * (a + b);
    c = 0.5 * (a - b);
    b = std::sqrt(a * b);
    a = an;
    pow2 *= 2.0;
    sum += pow2 * c * c;
  }
  K = M_PI / (2.0 * a);
  E = K * (1.0 - sum);
}

struct EulerRun {
  solver::ContinuationResult res;
  double PE = 0.0;
};

EulerRun euler_run(int cells, double max_factor = 1.3) {
  EulerRun r;
  const auto pr = statics_test::pinned_roller(cells);
  r.PE = M_PI * M_PI * statics_test::bending_stiffness(pr);
  solver::ContinuationOptions o;
  o.parameter = StaticParameter::end_load;
  o.max_value = max_factor * r.PE;
  o.initial_step = 0.1 * r.PE;
  o.max_step = 0.2 * r.PE;
  o.probes = {rod::probe_end_distance(), rod::probe_position(0.5, 1, "mid_y")};
  r.res = solver::continue_(pr, rod::straight_static_state(pr.base), o, comm());
  return r;
}

}  // namespace

TEST(StaticsContinuation, EulerBucklingIsAPitchforkConvergingAtOrderTwo) {
  std::vector<double> err;
  double PE = 0.0;
  for (int N : {10, 20, 40}) {
    const EulerRun r = euler_run(N);
    PE = r.PE;
    ASSERT_TRUE(r.res.completed) << r.res.message;
    ASSERT_EQ(r.res.bifurcations.size(), 1u);
    const auto& b = r.res.bifurcations[0];
    EXPECT_EQ(b.type, solver::BifurcationType::pitchfork);
    EXPECT_TRUE(b.located);
    EXPECT_EQ(b.unstable_before, 0);
    EXPECT_EQ(b.unstable_after, 1);
    err.push_back(b.parameter / PE - 1.0);
    if (root())
      std::printf("  Euler N=%d: P* = %.12f N, P_E = %.12f N, rel err %.3e (%d locate iterations, test fn %.1e)\n", N,
                  b.parameter, PE, err.back(), b.locate_iterations, b.test_function);
  }
  for (size_t i = 1; i < err.size(); ++i) {
    const double order = std::log2(err[i - 1] / err[i]);
    if (root()) std::printf("  Euler order %zu: %.4f\n", i, order);
    EXPECT_NEAR(order, 2.0, 0.1);
  }
  EXPECT_LT(std::abs(err.back()), 2e-3);
}

TEST(StaticsContinuation, BuckledElasticaMatchesClosedForm) {
  // theta0 = 60 deg at the ends: k = sin(30 deg) = 0.5.
  const double k = 0.5;
  double K = 0.0, E = 0.0;
  elliptic(k, K, E);
  const double P_ratio = 4.0 * K * K / (M_PI * M_PI), D_exact = 2.0 * (1.0 - E / K), w_exact = k / K;
  std::vector<double> P_at, D, w;
  std::vector<int> cells = {40, 80, 160};
  for (int N : cells) {
    const EulerRun r = euler_run(N, 1.05);
    ASSERT_EQ(r.res.bifurcations.size(), 1u);
    const auto pr = statics_test::pinned_roller(N);
    solver::ContinuationOptions o;
    o.parameter = StaticParameter::end_load;
    o.max_value = P_ratio * r.PE;  // land exactly on P/P_E = 4 K^2 / pi^2 of the discrete P_E
    o.min_value = 0.5 * r.PE;
    o.initial_step = 0.02 * r.PE;
    o.max_step = 0.05 * r.PE;
    o.stability.enabled = false;
    o.probes = {rod::probe_end_distance(), rod::probe_position(0.5, 1, "mid_y")};
    const auto br = solver::switch_branch(pr, r.res.bifurcations[0], 0.05, o, comm());
    ASSERT_TRUE(br.completed) << br.message;
    const auto& last = br.points.back();
    EXPECT_NEAR(last.parameter, o.max_value, 1e-12);
    D.push_back(1.0 - last.probes[0]);
    w.push_back(last.probes[1]);
    if (root())
      std::printf("  elastica N=%d: %zu points, D/L = %.10f (exact %.10f), w/L = %.10f (exact %.10f)\n", N,
                  br.points.size(), D.back(), D_exact, w.back(), w_exact);
    // The distributed answer equals the serial sparse-LU solution at the same load.
    auto prob = pr;
    prob.value(StaticParameter::end_load) = last.parameter;
    auto serial_state = last.state;
    const auto rep = rod::serial_newton(prob.model(), serial_state);
    ASSERT_TRUE(rep.converged) << rep.message;
    const double diff = solver::max_position_difference(serial_state, last.state);
    if (root()) std::printf("  elastica N=%d: distributed vs serial max |dr| = %.2e m\n", N, diff);
    EXPECT_LT(diff, 1e-8);
  }
  // The load is prescribed relative to the discrete P_E; Richardson extrapolation (order 2)
  // of D and w over the two finest meshes.
  const double D_rich = D[2] + (D[2] - D[1]) / 3.0, w_rich = w[2] + (w[2] - w[1]) / 3.0;
  const double oD = std::log2((D[0] - D[1]) / (D[1] - D[2])), ow = std::log2((w[0] - w[1]) / (w[1] - w[2]));
  if (root())
    std::printf("  elastica P/P_E = %.10f: Richardson D/L = %.10f (err %.2e, order %.3f), w/L = %.10f (err %.2e, order %.3f)\n",
                P_ratio, D_rich, D_rich - D_exact, oD, w_rich, w_rich - w_exact, ow);
  EXPECT_NEAR(D_rich, D_exact, 1e-6);
  EXPECT_NEAR(w_rich, w_exact, 1e-6);
  EXPECT_NEAR(oD, 2.0, 0.1);
  EXPECT_NEAR(ow, 2.0, 0.1);
}

TEST(StaticsContinuation, GreenhillHeavyColumnBucklesAsAPitchforkInGravity) {
  // Column along +j clamped at its foot, free top; gravity -j scaled by the factor.
  const double greenhill = 7.837347;  // q L^3 / (E I) at buckling
  std::vector<double> q;
  for (int N : {20, 40, 80}) {
    rod::StaticProblem pr;
    pr.base.props = rod::RodProperties::scene_rod();
    pr.base.num_cells = N;
    pr.base.length = 1.0;
    Mat3 R0;
    R0.row(0) = Vec3::UnitX().transpose();
    R0.row(1) = -Vec3::UnitZ().transpose();
    R0.row(2) = Vec3::UnitY().transpose();
    pr.base.left.type = rod::EndCondition::Type::clamped;
    pr.base.left.frame = R0;
    pr.base.right.type = rod::EndCondition::Type::free;
    pr.gravity = Vec3(0.0, -9.8, 0.0);
    const double EI = statics_test::bending_stiffness(pr), rhoA = pr.base.props.rhoA;
    solver::ContinuationOptions o;
    o.parameter = StaticParameter::gravity_factor;
    o.max_value = 1.0;
    o.initial_step = 0.1;
    o.max_step = 0.2;
    o.method = "Natural";
    o.probes = {rod::probe_position(1.0, 1, "top_y")};
    const auto res = solver::continue_(pr, rod::straight_static_state(pr.base, Vec3::Zero(), R0), o, comm());
    ASSERT_TRUE(res.completed) << res.message;
    ASSERT_EQ(res.bifurcations.size(), 1u);
    const auto& b = res.bifurcations[0];
    EXPECT_EQ(b.type, solver::BifurcationType::pitchfork);
    EXPECT_EQ(b.unstable_before, 0);
    EXPECT_EQ(b.unstable_after, 2);  // circular section: buckling along i and along k together
    q.push_back(rhoA * 9.8 * b.parameter / EI);
    if (root())
      std::printf("  Greenhill N=%d: gravity factor %.10f, q L^3/EI = %.8f (Greenhill %.6f), top lowered by %.2e m\n", N,
                  b.parameter, q.back(), greenhill, 1.0 - b.probes[0]);
  }
  const double order = std::log2((q[0] - q[1]) / (q[1] - q[2]));
  const double rich = q[2] + (q[2] - q[1]) / 3.0;
  if (root()) std::printf("  Greenhill order %.3f, Richardson %.8f (err %.2e)\n", order, rich, rich - greenhill);
  EXPECT_NEAR(order, 2.0, 0.1);
  EXPECT_NEAR(rich, greenhill, 1e-5);
}
