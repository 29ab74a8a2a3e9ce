#pragma once
// The hinged arch of the reference scenes (initial_state: arch) formed in one process without
// Trilinos: the same arch as solver::form_arch (arch_formation.hpp, LOCA continuation with
// branch switching at the Euler pitchfork), reached by another path on the same static
// discretisation (docs/statics.md, "The arch in one process"):
//  1. the Euler load: the compressive end load at which the Jacobian of the straight
//     pinned-roller rod turns singular (the sign of its determinant, Illinois' regula falsi);
//  2. its null vector by inverse iteration (the buckling mode, turned upwards);
//  3. the ends pinned and moved together along k from L to dz (the straight rod cannot follow:
//     each solve has only the buckled state), each Newton solve starting from the last state,
//     the first from the straight rod plus the mode at the amplitude of the elastica's small
//     deflections;
//  4. gravity raised from 0 to g by load steps.
// The state is an equilibrium of the same problem on the same branch: it equals the LOCA arch
// to the Newton tolerances (test_arch_in_one_process). The LU in band storage
// (core/sparse_lu.hpp; rod::StaticSolver's), on the in-plane rows and unknowns where the
// problem splits about the plane of j and k.
#include <string>
#include <vector>

#include "traverse/rod/static_problem.hpp"

namespace traverse::solver {

struct OneProcessArch {
  bool ok = false;
  std::string message;          ///< which stage failed and why (empty when ok)
  /// Both ends pinned about i (left at the origin, right at dz k), gravity factor 1 of
  /// -gravity j, as ArchFormation::problem.
  rod::StaticProblem problem;
  std::vector<rod::StaticNode> state;  ///< the formed arch under gravity, at rest
  double euler_load = 0.0;      ///< the pitchfork of the straight rod [N]
  double forming_load = 0.0;    ///< compressive end load at end-to-end distance dz, no gravity [N]
  int displacement_steps = 0;   ///< solves of step 3
  int newton_iterations = 0;    ///< of steps 3 and 4
};

/// The rod `props` (straight: no intrinsic curvature) with `num_cells` cells and length L
/// formed into an arch whose ends are dz apart, under gravity g [m/s^2] along -j. Not ok (and
/// why) when the rod is curved, the straight rod has no pitchfork up to 1.6 times the Euler
/// load of its weaker axis, its first buckling mode leaves the plane of j and k, or a solve
/// fails.
OneProcessArch form_arch_in_one_process(const rod::RodProperties& props, int num_cells, double length, double dz,
                                        double gravity);

}  // namespace traverse::solver
