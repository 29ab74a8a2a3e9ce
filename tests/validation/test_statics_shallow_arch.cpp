// The shallow hinged arch of the scenes (dz = 0.864545 m, F = 2 N): continuation in the load
// position sigma with the library's default step control (initial step 0.01, max step 0.02,
// as inputs/statics/shallow_arch_sigma.yaml). The planar path ends in an in-plane fold (the
// snap): located, 0 -> 1 unstable mode there, null vector in the plane of the arch, the
// largest sigma of the branch; the continuation turns at it and follows the unstable branch
// back to sigma = 0, which loses a second mode at an out-of-plane pitchfork. The fold's sigma
// and end compression converge at order 2 in ds over N = 100, 200, 400 cells.
// (On coarser meshes the fold is absent: F = 2 N lies close to the cusp where the fold pair
// is born, and with N = 50 cells the planar path stays stable, lowest omega^2 ~ 33 s^-2 -
// measured, see docs/statics.md; not asserted here.)
#include <gtest/gtest.h>

#include <Tpetra_Core.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "traverse/solver/arch_formation.hpp"

using namespace traverse;

namespace {

solver::Comm comm() { return Tpetra::getDefaultComm(); }

constexpr double kDz = 0.864545, kF = 2.0;

struct NullVectorParts {
  double lateral = 0.0;   ///< max |x| (out of the arch's plane)
  double in_plane = 0.0;  ///< max |y|, |z|
};

NullVectorParts parts(const solver::Bifurcation& b) {
  NullVectorParts p;
  for (const auto& v : b.null_vector) {
    p.lateral = std::max(p.lateral, std::abs(v(0)));
    p.in_plane = std::max({p.in_plane, std::abs(v(1)), std::abs(v(2))});
  }
  return p;
}

struct FoldRun {
  solver::ContinuationResult r;
  double sigma = 0.0, compression = 0.0;
};

/// Forms the arch on N cells and continues in sigma from 0; `past_fold`: stop at the first
/// unstable point (just past the fold), else follow the branch to its end.
FoldRun fold_run(int N, bool past_fold) {
  solver::ArchOptions ao;
  ao.num_cells = N;
  ao.end_distance = kDz;
  const auto a = solver::form_arch(rod::RodProperties::scene_rod(), ao, comm());
  EXPECT_TRUE(a.ok) << a.message;
  FoldRun out;
  if (!a.ok) return out;
  solver::ContinuationOptions o;  // library defaults otherwise (Newton iterations, acceptance)
  o.initial_step = 0.01;
  o.max_step = 0.02;
  o.max_steps = 400;
  if (past_fold) o.stop = [](const solver::ContinuationPoint& p) { return p.unstable_modes > 0; };
  out.r = solver::sweep_load_position(a, kF, 0.0, 1.0, o, comm());
  return out;
}

/// The checks on the fold common to every mesh; returns false when there is no fold to check.
bool check_fold(int N, FoldRun& f) {
  const auto& r = f.r;
  EXPECT_TRUE(r.completed) << r.message;
  EXPECT_GE(r.bifurcations.size(), 1u) << "N = " << N << ": no fold (" << r.message << ")";
  if (r.bifurcations.empty()) return false;
  const auto& b = r.bifurcations[0];
  const NullVectorParts nv = parts(b);
  std::printf("  N=%d: %s at sigma = %.10f m, |n(L).k| = %.8f N, located %d (%d iterations, test fn %.2e 1/s^2), "
              "null vector max|x| %.1e max|y,z| %.3f; %zu points, %d steps rejected\n",
              N, solver::to_string(b.type).c_str(), b.parameter, b.probes[0], b.located, b.locate_iterations,
              b.test_function, nv.lateral, nv.in_plane, r.points.size(), r.rejected_steps);
  EXPECT_EQ(b.type, solver::BifurcationType::fold);
  EXPECT_TRUE(b.located);
  EXPECT_EQ(b.unstable_before, 0);
  EXPECT_EQ(b.unstable_after, 1);
  // The test function (the crossing omega^2) is zero at the located state, against values of
  // O(10 .. 300) 1/s^2 along the branch.
  EXPECT_LT(std::abs(b.test_function), 1e-6);
  // In-plane snap: the null vector has no lateral part (round-off; max |r| = 1 in the plane).
  EXPECT_LT(nv.lateral, 1e-10);
  EXPECT_NEAR(nv.in_plane, 1.0, 1e-12);
  // A fold of the sigma-path: sigma is largest there. Every computed point lies below it, and
  // the last point before it is within one continuation step (the step control shrinks there).
  double top = -1.0;
  for (const auto& p : r.points) top = std::max(top, p.parameter);
  EXPECT_LE(top, b.parameter + 1e-10);
  EXPECT_GT(top, b.parameter - 0.02);
  // Stability flips exactly there: 0 unstable modes on every point before it, 1 just after.
  const size_t k = static_cast<size_t>(b.after_point);
  for (size_t i = 0; i < k; ++i) EXPECT_EQ(r.points[i].unstable_modes, 0) << "point " << i;
  EXPECT_EQ(r.points[k].unstable_modes, 1);
  f.sigma = b.parameter;
  f.compression = b.probes[0];
  return true;
}

double order(double a, double b, double c) { return std::log2((a - b) / (b - c)); }

}  // namespace

TEST(StaticsShallowArch, FoldLocatedTurnedAndConvergingAtOrderTwo) {
  std::vector<double> sig, comp;
  for (int N : {100, 200, 400}) {
    FoldRun f = fold_run(N, N != 100);
    ASSERT_TRUE(check_fold(N, f));
    sig.push_back(f.sigma);
    comp.push_back(f.compression);
    if (N != 100) continue;
    // N = 100: the whole branch. It turns at the fold (sigma decreases afterwards), keeps one
    // unstable mode until an out-of-plane pitchfork (1 -> 2), and ends at the bound sigma = 0
    // on the unstable branch.
    const auto& r = f.r;
    ASSERT_EQ(r.bifurcations.size(), 2u) << r.message;
    const auto& fold = r.bifurcations[0];
    const auto& pf = r.bifurcations[1];
    const NullVectorParts nv = parts(pf);
    std::printf("  N=100 unstable branch: %s at sigma = %.10f m (|n(L).k| = %.6f N), %d -> %d unstable, located %d, "
                "null vector max|x| %.3f max|y,z| %.1e; ends at sigma = %.3g with %d unstable modes (%s)\n",
                solver::to_string(pf.type).c_str(), pf.parameter, pf.probes[0], pf.unstable_before, pf.unstable_after,
                pf.located, nv.lateral, nv.in_plane, r.points.back().parameter, r.points.back().unstable_modes,
                r.message.c_str());
    EXPECT_EQ(pf.type, solver::BifurcationType::pitchfork);
    EXPECT_TRUE(pf.located);
    EXPECT_EQ(pf.unstable_before, 1);
    EXPECT_EQ(pf.unstable_after, 2);
    EXPECT_NEAR(nv.lateral, 1.0, 1e-12);
    EXPECT_LT(nv.in_plane, 1e-10);
    EXPECT_LT(pf.parameter, fold.parameter);
    const size_t kf = static_cast<size_t>(fold.after_point), kp = static_cast<size_t>(pf.after_point);
    for (size_t i = 1; i < r.points.size(); ++i) {
      const double dp = r.points[i].parameter - r.points[i - 1].parameter;
      if (i < kf) {
        EXPECT_GT(dp, 0.0) << "point " << i;
      } else {
        if (i > kf) {
          EXPECT_LT(dp, 0.0) << "point " << i;
        }
        EXPECT_EQ(r.points[i].unstable_modes, i < kp ? 1 : 2) << "point " << i;
      }
    }
    EXPECT_TRUE(r.completed);
    EXPECT_NEAR(r.points.back().parameter, 0.0, 1e-12);
  }
  const double os = order(sig[0], sig[1], sig[2]), oc = order(comp[0], comp[1], comp[2]);
  std::printf("  fold: order sigma %.3f, |n(L).k| %.3f; Richardson (order 2, N = 200/400): sigma = %.8f m, "
              "|n(L).k| = %.8f N\n",
              os, oc, sig[2] + (sig[2] - sig[1]) / 3.0, comp[2] + (comp[2] - comp[1]) / 3.0);
  // Second order in ds, asserted within 0.3 (measured 2.15 and 2.13 over these meshes; 2.14
  // and 2.12 over 200/400/800, so the pre-asymptotic part is small but not zero).
  EXPECT_NEAR(os, 2.0, 0.3);
  EXPECT_NEAR(oc, 2.0, 0.3);
  // Monotone convergence (the fold moves left and its compression falls as ds shrinks).
  EXPECT_GT(sig[0], sig[1]);
  EXPECT_GT(sig[1], sig[2]);
}
