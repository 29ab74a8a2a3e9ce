#pragma once
// Shared set-up of the MPI solver tests: the models, the reference comparison, rank-0 output.
#include <Teuchos_Comm.hpp>
#include <Tpetra_Core.hpp>
#include <algorithm>
#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <string>

#include "reference_stepper.hpp"
#include "traverse/solver/distributed_stepper.hpp"

namespace traverse::solver::test {

inline Teuchos::RCP<const Teuchos::Comm<int>> comm() { return Tpetra::getDefaultComm(); }
inline int ranks() { return comm()->getSize(); }

/// printf on rank 0 only.
inline void say(const char* fmt, ...) {
  if (comm()->getRank() != 0) return;
  va_list ap;
  va_start(ap, fmt);
  std::vfprintf(stdout, fmt, ap);
  va_end(ap);
  std::fflush(stdout);
}

/// Scene rod (r = 5 mm, E = 250 MPa), L = 1 m along k, clamped at s = 0 and free at s = L,
/// gravity -9.81 j, plus a moving point force -0.05 j N travelling at 2 m/s from s = 0.1 m.
inline rod::RodModel cantilever(int N, bool moving_load = true) {
  rod::RodModel m;
  m.props = rod::RodProperties::scene_rod();
  m.num_cells = N;
  m.length = 1.0;
  m.left = rod::EndCondition::make_clamped();
  m.right = rod::EndCondition::make_free();
  m.loads.gravity = Vec3(0.0, -9.81, 0.0);
  if (moving_load)
    m.loads.point_forces.push_back(
        {[](double) { return Vec3(0.0, -0.05, 0.0); }, [](double t) { return 0.1 + 2.0 * t; }});
  return m;
}

/// max |a - b| of the unknowns (y and ys) and of the orientations R over all nodes.
inline double max_difference(const rod::RodState& a, const rod::RodState& b) {
  double d = 0.0;
  for (size_t j = 0; j < a.nodes.size(); ++j) {
    d = std::max(d, (a.nodes[j].y - b.nodes[j].y).cwiseAbs().maxCoeff());
    d = std::max(d, (a.nodes[j].ys - b.nodes[j].ys).cwiseAbs().maxCoeff());
    d = std::max(d, (a.nodes[j].R - b.nodes[j].R).cwiseAbs().maxCoeff());
  }
  return d;
}

/// max |a.yt - b.yt|: the time-derivative history, (y_new - y_old) / (gt dt) - ..., which
/// magnifies the converged unknowns' round-off by 1 / (gt dt).
inline double max_yt_difference(const rod::RodState& a, const rod::RodState& b) {
  double d = 0.0;
  for (size_t j = 0; j < a.nodes.size(); ++j)
    d = std::max(d, (a.nodes[j].yt - b.nodes[j].yt).cwiseAbs().maxCoeff());
  return d;
}

/// Named solver parameter sets.
inline Teuchos::ParameterList solver_params(const std::string& name) {
  Teuchos::ParameterList p;
  p.set("Verbose", false);
  if (name == "KLU2") {
    p.set("Linear Solver", "KLU2");
  } else if (name == "auto") {
    p.set("Linear Solver", "auto");
  } else {
    p.set("Linear Solver", "GMRES");
    p.set("Preconditioner", name.substr(name.find('+') + 1));
  }
  return p;
}

}  // namespace traverse::solver::test
