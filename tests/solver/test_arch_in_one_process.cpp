// The arch formed in one process without Trilinos (solver/arch_in_one_process.hpp) against the
// LOCA formation (solver::form_arch) on the scene rod: the shallow (dz = 0.864545 m) and the deep
// (dz = 0.529689 m) arch, 100 cells: the same Euler load, the same end load at dz and the same
// state under gravity, to the Newton tolerances.
#include <gtest/gtest.h>

#include <Tpetra_Core.hpp>

#include <cmath>
#include <cstdio>

#include "traverse/solver/arch_formation.hpp"
#include "traverse/solver/arch_in_one_process.hpp"

namespace traverse {
namespace {

TEST(ArchInOneProcess, IsTheArchOfTheContinuation) {
  const rod::RodProperties props = rod::RodProperties::scene_rod();
  for (const double dz : {0.864545, 0.529689}) {
    const int N = 100;
    solver::ArchOptions ao;
    ao.num_cells = N;
    ao.end_distance = dz;
    const solver::ArchFormation loca = solver::form_arch(props, ao, Tpetra::getDefaultComm());
    ASSERT_TRUE(loca.ok) << loca.message;
    const solver::OneProcessArch one = solver::form_arch_in_one_process(props, N, 1.0, dz, 9.8);
    ASSERT_TRUE(one.ok) << one.message;
    ASSERT_EQ(one.state.size(), loca.state.size());
    double dr = 0.0, dR = 0.0, dn = 0.0, dk = 0.0;
    for (size_t j = 0; j < one.state.size(); ++j) {
      const auto& a = one.state[j];
      const auto& b = loca.state[j];
      dr = std::max(dr, (a.x.segment<3>(rod::svar::r) - b.x.segment<3>(rod::svar::r)).cwiseAbs().maxCoeff());
      dR = std::max(dR, (a.frame() - b.frame()).cwiseAbs().maxCoeff());
      dk = std::max(dk, (a.x.segment<3>(rod::svar::kappa) - b.x.segment<3>(rod::svar::kappa)).cwiseAbs().maxCoeff());
      dn = std::max(dn, (a.frame().transpose() * a.x.segment<3>(rod::svar::n) -
                         b.frame().transpose() * b.x.segment<3>(rod::svar::n)).cwiseAbs().maxCoeff());
    }
    // LOCA reports the end load at its first continuation point past dz; this formation the
    // end load at dz itself (the pinned state before gravity).
    const double fixed_at_dz = rod::probe_end_compression(Vec3::UnitZ())
                                   .eval(rod::pinned_arch_problem(loca.forming.final_problem, dz).model(),
                                         loca.loading.points.front().state);
    std::printf("dz = %g m: Euler load %.12g / %.12g N (one process / continuation), end load at dz %.10g / %.10g N "
                "(continuation's first point past dz: %.10g N); state: max |dr| %.2e m, |dR| %.2e, |dkappa| %.2e 1/m, "
                "|dn| %.2e N; %d displacement steps, %d Newton iterations\n",
                dz, one.euler_load, loca.euler_load, one.forming_load, fixed_at_dz, loca.forming_load, dr, dR, dk, dn,
                one.displacement_steps, one.newton_iterations);
    EXPECT_NEAR(one.euler_load, loca.euler_load, 1e-9 * loca.euler_load);
    EXPECT_NEAR(one.forming_load, fixed_at_dz, 1e-8 * fixed_at_dz);
    EXPECT_LT(dr, 1e-9);
    EXPECT_LT(dR, 1e-8);
    EXPECT_LT(dk, 1e-7);
    EXPECT_LT(dn, 1e-8);
    EXPECT_EQ(one.problem.value(rod::StaticParameter::gravity_factor), 1.0);
    EXPECT_EQ(one.problem.value(rod::StaticParameter::end_position), dz);
  }
}

// What cannot be formed says so: the ends farther apart than the rod is long; a curved rod; a
// section a hundred times weaker about d2, whose in-plane pitchfork (100 times the Euler load of
// its weaker axis) and out-of-plane one (4 times: the pins hold the ends' turn about j) lie
// beyond the search, as the continuation's (which stops at 1.1 times).
TEST(ArchInOneProcess, RefusesWhatItCannotForm) {
  const rod::RodProperties scene = rod::RodProperties::scene_rod();
  const solver::OneProcessArch a = solver::form_arch_in_one_process(scene, 20, 1.0, 1.2, 9.8);
  EXPECT_FALSE(a.ok);
  EXPECT_NE(a.message.find("end_to_end"), std::string::npos) << a.message;
  rod::RodProperties curved = scene;
  curved.kappa0 = Vec3(0.5, 0.0, 0.0);
  const solver::OneProcessArch b = solver::form_arch_in_one_process(curved, 20, 1.0, 0.9, 9.8);
  EXPECT_FALSE(b.ok);
  EXPECT_NE(b.message.find("intrinsic curvature"), std::string::npos) << b.message;
  rod::RodProperties thin = scene;
  thin.K(1) = 0.01 * thin.K(0);  // EI about d2 a hundredth of that about d1
  const solver::OneProcessArch c = solver::form_arch_in_one_process(thin, 20, 1.0, 0.9, 9.8);
  std::printf("a section 100 times weaker about d2: %s\n", c.ok ? "formed" : c.message.c_str());
  EXPECT_FALSE(c.ok);
  EXPECT_NE(c.message.find("no Euler pitchfork"), std::string::npos) << c.message;
}

}  // namespace
}  // namespace traverse
