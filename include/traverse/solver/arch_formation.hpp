#pragma once
// The hinged arches of the reference scenes as a statics pipeline (docs/statics.md):
// buckle a straight pinned-roller rod upwards by a quasi-statically increasing compressive end
// load (branch switching at the Euler pitchfork), continue until the end-to-end distance
// reaches dz, fix the right end there (pinned), raise gravity from 0 to g. The resulting
// static state is the initial state of the dynamics (rod::dynamic_state_from_static) and of
// the load-position sweep (sweep_load_position).
#include <string>
#include <vector>

#include "traverse/solver/static_continuation.hpp"

namespace traverse::solver {

struct ArchOptions {
  double length = 1.0;          ///< L [m]
  int num_cells = 100;
  double end_distance = 0.864545;  ///< dz [m] (shallow arch; deep arch 0.529689)
  double gravity = 9.8;         ///< [m/s^2], along -j
  Teuchos::ParameterList solver;  ///< linear solver keys (solver_parameters.hpp)
  bool verbose = false;
};

struct ArchFormation {
  bool ok = false;
  std::string message;           ///< what failed (empty when ok)
  /// Both ends pinned about i (left at the origin, right at dz k), gravity factor 1 of
  /// -gravity j; end_position = dz. Add the point load with has_point_load / values.
  rod::StaticProblem problem;
  std::vector<rod::StaticNode> state;  ///< the formed arch under gravity, at rest
  double euler_load = 0.0;       ///< located Euler pitchfork P [N]
  double forming_load = 0.0;     ///< compressive end load when the ends reached dz (no gravity) [N]
  ContinuationResult buckling;   ///< straight branch in the end load (with the pitchfork)
  ContinuationResult forming;    ///< buckled branch in the end load up to dz
  ContinuationResult loading;    ///< gravity factor 0 -> 1
};

/// The scene rod (rod::RodProperties) formed into an arch. Collective over comm.
ArchFormation form_arch(const rod::RodProperties& props, const ArchOptions& options, const Comm& comm);

/// Continuation in the load position sigma of a vertical point load F (-F j) on a formed arch,
/// from sigma = sigma_start to sigma_end, with stability and bifurcations; probes
/// "end_compression" (|n(L) . k| [N]), "mid_x", "mid_y" (midpoint position [m]).
/// `base` sets steps, tolerances and solver (its parameter, bounds and probes are replaced).
ContinuationResult sweep_load_position(const ArchFormation& arch, double F, double sigma_start, double sigma_end,
                                       const ContinuationOptions& base, const Comm& comm,
                                       const PointCallback& on_point = {});

/// The probes used by sweep_load_position.
std::vector<rod::StaticProbe> arch_probes(double length);

}  // namespace traverse::solver
