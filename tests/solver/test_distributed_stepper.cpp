// The distributed rod stepper against the serial ReferenceStepper, on 1 and 2 ranks, for each
// linear solver valid on that rank count; the KLU2 rule; Newton convergence; step
// subdivision and StepFailure; reuse of W, graph and preconditioner.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include "rod_mpi_test_util.hpp"

namespace traverse::solver {
namespace {

using test::say;

std::vector<std::string> solvers_for_this_rank_count() {
  if (test::ranks() == 1)
    return {"auto", "KLU2", "GMRES+SCHWARZ", "GMRES+BLOCK_TRIDIAGONAL", "GMRES+ILUT", "GMRES+RILUK"};
  return {"auto", "KLU2", "GMRES+SCHWARZ", "GMRES+BLOCK_TRIDIAGONAL", "GMRES+ILUT"};
}

/// Steps both steppers `steps` times by dt, returns the max difference seen at any step.
struct Comparison {
  double unknowns = 0.0;  ///< max |diff| of y, ys and R over all nodes and steps
  double yt = 0.0;        ///< max |diff| of the yt history
  std::string resolved;
  int max_newton = 0, total_newton = 0, total_linear = 0;
};

Comparison run_against_reference(const std::string& name, int N, double dt, int steps);

/// run_against_reference with any exception turned into a test failure (the loop goes on).
bool compare(const std::string& name, int N, double dt, int steps, Comparison& c) {
  try {
    c = run_against_reference(name, N, dt, steps);
    return true;
  } catch (const std::exception& e) {
    ADD_FAILURE() << name << ": " << e.what();
    return false;
  }
}

Comparison run_against_reference(const std::string& name, int N, double dt, int steps) {
  const rod::RodModel model = test::cantilever(N);
  DistributedStepper ds(model, test::comm(), test::solver_params(name));
  rod::ReferenceStepper ref(model);
  rod::RodState s = rod::straight_rest_state(N, model.length);
  ds.set_state(s);
  Comparison c;
  for (int i = 0; i < steps; ++i) {
    const StepReport r = ds.step(dt);
    const rod::ReferenceStepReport rr = ref.step(s, dt);
    EXPECT_TRUE(rr.converged);
    EXPECT_EQ(r.substeps, 1);
    c.max_newton = std::max(c.max_newton, r.newton_iterations);
    c.total_newton += r.newton_iterations;
    c.total_linear += r.linear_iterations;
    const rod::RodState g = ds.gather_state();
    c.unknowns = std::max(c.unknowns, test::max_difference(g, s));
    c.yt = std::max(c.yt, test::max_yt_difference(g, s));
    EXPECT_NEAR(ds.time(), s.t, 1e-15);
  }
  c.resolved = ds.resolved_linear_solver();
  return c;
}

TEST(DistributedStepper, OneStepMatchesReference) {
  for (const auto& name : solvers_for_this_rank_count()) {
    const double dt = 2e-3;
    Comparison c;
    if (!compare(name, 24, dt, 1, c)) continue;
    say("[%d ranks] one step, %-14s -> %s: max|diff| y,ys,R %.3e, yt %.3e, Newton its %d, "
        "linear its %d\n", test::ranks(), name.c_str(), c.resolved.c_str(), c.unknowns, c.yt,
        c.max_newton, c.total_linear);
    EXPECT_LT(c.unknowns, 1e-10) << name;
    EXPECT_LT(c.yt * 0.5 * dt, 1e-10) << name;
  }
}

TEST(DistributedStepper, ThirtyStepsMatchReference) {
  for (const auto& name : solvers_for_this_rank_count()) {
    const double dt = 2e-3;
    Comparison c;
    if (!compare(name, 24, dt, 30, c)) continue;
    say("[%d ranks] 30 steps, %-14s: max|diff| over all steps y,ys,R %.3e, yt %.3e, max Newton "
        "its/step %d, linear its total %d\n", test::ranks(), name.c_str(), c.unknowns, c.yt,
        c.max_newton, c.total_linear);
    EXPECT_LT(c.unknowns, 1e-10) << name;
    EXPECT_LT(c.yt * 0.5 * dt, 1e-10) << name;
    // The block-tridiagonal LU is exact on any rank count: one GMRES iteration per Newton
    // iteration (on 1 rank it is used directly, without GMRES), and 'auto' is that LU, direct.
    if (name == "GMRES+BLOCK_TRIDIAGONAL") {
      EXPECT_LE(c.total_linear, c.total_newton) << name;
    }
    if (name == "auto") {
      EXPECT_NE(c.resolved.find("block-tridiagonal LU (direct"), std::string::npos) << c.resolved;
    }
  }
}

TEST(DistributedStepper, Klu2IsReroutedOnSeveralRanksOrRefused) {
  const rod::RodModel model = test::cantilever(12);
  DistributedStepper ds(model, test::comm(), test::solver_params("KLU2"));
  say("[%d ranks] KLU2 requested -> resolved: %s\n", test::ranks(), ds.resolved_linear_solver().c_str());
  if (test::ranks() == 1) {
    EXPECT_FALSE(ds.linear_solver_rerouted());
    EXPECT_EQ(ds.resolved_linear_solver(), "Amesos2 KLU2 (direct)");
  } else {
    EXPECT_TRUE(ds.linear_solver_rerouted());
    EXPECT_EQ(ds.requested_linear_solver(), "Amesos2 KLU2 (direct)");
    EXPECT_NE(ds.resolved_linear_solver().find("Belos GMRES + Ifpack2 SCHWARZ"), std::string::npos);
    EXPECT_NE(ds.resolved_linear_solver().find("rerouted from Amesos2 KLU2"), std::string::npos);
    Teuchos::ParameterList refuse = test::solver_params("KLU2");
    refuse.set("On Broken Direct Solver", "refuse");
    try {
      DistributedStepper bad(model, test::comm(), refuse);
      ADD_FAILURE() << "KLU2 on several ranks with 'refuse' was accepted";
    } catch (const std::invalid_argument& e) {
      say("refused as expected: %s\n", e.what());
      EXPECT_NE(std::string(e.what()).find("refused"), std::string::npos);
    }
  }
  // The answer is right whatever runs (one step against the reference).
  rod::ReferenceStepper ref(model);
  rod::RodState s = rod::straight_rest_state(12, 1.0);
  ds.step(2e-3);
  ref.step(s, 2e-3);
  const double d = test::max_difference(ds.gather_state(), s);
  say("KLU2 request, one step: max|diff| = %.3e\n", d);
  EXPECT_LT(d, 1e-10);
}

TEST(DistributedStepper, NewtonConvergesQuadratically) {
  const rod::RodModel model = test::cantilever(24);
  DistributedStepper ds(model, test::comm(), test::solver_params(test::ranks() == 1 ? "KLU2" : "GMRES+SCHWARZ"));
  for (int i = 0; i < 5; ++i) ds.step(2e-3);
  const StepReport r = ds.step(4e-2);  // a moderate step from a moving state
  const auto& h = r.last.residual_history;
  say("[%d ranks] residual history (max|f|):", test::ranks());
  for (double v : h) say(" %.3e", v);
  say("\n");
  ASSERT_GE(h.size(), 3u);
  EXPECT_LE(r.last.iterations, 5);
  // Convergence order estimates log(r_{k+1}/r_k) / log(r_k/r_{k-1}) above round-off.
  // (Pairs whose newer residual is within 100x of the round-off floor ~1e-15 are skipped.)
  double best = 0.0;
  int estimates = 0;
  for (size_t k = 1; k + 1 < h.size(); ++k) {
    if (h[k + 1] < 1e-13) break;
    ++estimates;
    const double q = std::log(h[k + 1] / h[k]) / std::log(h[k] / h[k - 1]);
    say("order estimate %zu: %.3f\n", k, q);
    best = std::max(best, q);
  }
  ASSERT_GE(estimates, 1);
  EXPECT_GT(best, 1.7);
}

TEST(DistributedStepper, SubdividesAFailingStepAndThrowsWithoutRetries) {
  const rod::RodModel model = test::cantilever(16);
  Teuchos::ParameterList p = test::solver_params(test::ranks() == 1 ? "KLU2" : "GMRES+SCHWARZ");
  p.set("Max Newton Iterations", 3);
  p.set("Max Subdivision Depth", 6);
  DistributedStepper ds(model, test::comm(), p);
  const double dt = 0.1;  // absurd for this cantilever: it swings far in one step
  const StepReport r = ds.step(dt);
  say("[%d ranks] dt = %.3g s: %d failed attempts, %d substeps, depth %d, Newton its %d\n",
      test::ranks(), dt, r.failed_attempts, r.substeps, r.max_depth, r.newton_iterations);
  EXPECT_GE(r.failed_attempts, 1);
  EXPECT_GE(r.max_depth, 1);
  EXPECT_DOUBLE_EQ(ds.time(), dt);

  // Without retries the same step throws StepFailure and leaves the state unchanged.
  p.set("Max Subdivision Depth", 0);
  DistributedStepper strict(model, test::comm(), p);
  strict.step(1e-3);
  const rod::RodState before = strict.gather_state();
  try {
    strict.step(dt);
    ADD_FAILURE() << "no StepFailure";
  } catch (const StepFailure& e) {
    say("StepFailure: %s\n", e.what());
    EXPECT_DOUBLE_EQ(e.time(), 1e-3);
    EXPECT_DOUBLE_EQ(e.step(), dt);
    EXPECT_EQ(e.depth(), 0);
    EXPECT_FALSE(e.report().converged);
    EXPECT_NE(e.report().status.find("failed"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("t = 0.001"), std::string::npos);
  }
  EXPECT_DOUBLE_EQ(strict.time(), 1e-3);
  EXPECT_EQ(test::max_difference(strict.gather_state(), before), 0.0);
}

TEST(DistributedStepper, NoJacobianAtTheIterateWhereTheLastSolveConverged) {
  // Consecutive steps take as many Newton iterations, so the residual at the iterate where the
  // last solve converged is evaluated alone: one Jacobian per Newton iteration (a step of k
  // iterations evaluates k + 1 residuals), not one per residual. (That the residual alone has
  // the same bits as the full evaluation's: RodKernels.ResidualAloneIsTheSameResidual.)
  const rod::RodModel model = test::cantilever(20);
  DistributedStepper ds(model, test::comm(), test::solver_params("auto"));
  ds.step(2e-3);  // the first solve sets the expected count
  const ReuseCounters c0 = ds.reuse_counters();
  int newton = 0;
  const int steps = 6;
  for (int i = 0; i < steps; ++i) newton += ds.step(2e-3).newton_iterations;
  const ReuseCounters c1 = ds.reuse_counters();
  const long fills = c1.jacobian_fills - c0.jacobian_fills;
  const int residuals = c1.residual_evaluations - c0.residual_evaluations;
  say("[%d ranks] %d steps, %d Newton iterations, %d residuals, %ld Jacobians\n", test::ranks(), steps, newton,
      residuals, fills);
  EXPECT_EQ(residuals, newton + steps);
  EXPECT_GE(fills, newton);
  EXPECT_LT(fills, newton + steps);
}

TEST(DistributedStepper, ReusesGraphMatrixAndPreconditioner) {
  const rod::RodModel model = test::cantilever(20);
  DistributedStepper ds(model, test::comm(), test::solver_params("GMRES+SCHWARZ"));
  const void* W = ds.jacobian_address();
  EXPECT_EQ(ds.graph_address(), ds.mesh_graph_address());
  int newton = 0;
  for (int i = 0; i < 4; ++i) {
    newton += ds.step(2e-3).newton_iterations;
    EXPECT_EQ(ds.jacobian_address(), W);
    EXPECT_EQ(ds.graph_address(), ds.mesh_graph_address());
  }
  const ReuseCounters c = ds.reuse_counters();
  say("[%d ranks] 4 steps, %d Newton its: W evaluations %d, preconditioners created %d, "
      "initialized %d, computed %d\n", test::ranks(), newton, c.jacobian_evaluations,
      c.preconditioners_created, c.preconditioner_initializations, c.preconditioner_computations);
  EXPECT_EQ(c.preconditioners_created, 1);
  EXPECT_EQ(c.preconditioner_computations, newton);
  if (test::ranks() == 1) {
    EXPECT_EQ(c.preconditioner_initializations, 1);
  }
}

}  // namespace
}  // namespace traverse::solver
