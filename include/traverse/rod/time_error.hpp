#pragma once
// Local error in time of the rod's generalised-alpha step (docs/adaptive.md).
//
// Five groups of three components per node can be controlled:
//  * position and orientation (the default): the step moves each node's position by the
//    trapezoidal rule on its fixed-frame velocity v = R^T u, and its frame by the midpoint
//    rule on the fixed-frame spin w = R^T omega; the local error of either is h^3 x'' / 12
//    (x = v or w), with x'' the second divided difference of the new level and the two
//    accepted levels before it. These displacement-type errors weigh a mode of frequency
//    omega_k by its displacement, not its velocity: the bending waves of the grid scale that a
//    moving load excites do not force tiny steps unless they move the rod.
//  * u, omega, kappa (the state): the new level against the quadratic extrapolation of the
//    three accepted levels before it. The levels lie on the numerical trajectory, whose
//    global error is smooth, so the extrapolation's error is that of the trajectory itself:
//    y - y_pred = K y''' with K = h (h + h1)(h + h1 + h2) / 6 (h1, h2 the two steps before),
//    and the estimate of the local error c h^3 y''' (c = local_error_constant, 1/12 for the
//    box scheme's trapezoidal rule) is e = c h^3 / K (y - y_pred), for any step history. (The
//    textbook Milne factor c h^3 / (c h^3 + K) assumes the earlier levels on the exact
//    solution through y_n; here they are not, and it would underestimate by 12/13.)
// Both use the levels only, never the history yt, which in the box scheme carries an
// alternating mode when the start is not consistent. n is algebraic (no time derivative) and
// is not controlled.
//
// Without three levels (the first step of a run) the step is checked by step doubling: one
// step of h against two of h / 2 from the same level, e = (x_half - x_full) / (2^2 - 1) for the
// state and for the displacements, the error of the two half steps, which are kept.
#include <array>
#include <vector>

#include "traverse/core/types.hpp"
#include "traverse/rod/alpha_parameters.hpp"
#include "traverse/rod/rod_state.hpp"

namespace traverse::rod {

/// The controlled groups, three components each.
enum class ErrorGroup { position = 0, orientation = 1, u = 2, omega = 3, kappa = 4 };
inline constexpr int kErrorGroups = 5;
using GroupValues = std::array<double, kErrorGroups>;

/// One node's quantities at one level: v = R^T u, w = R^T omega (the rates of the position and
/// orientation groups), then u, omega, kappa.
using NodeLevel = Eigen::Matrix<double, 15, 1>;
NodeLevel node_level(const RodNode& n);

/// The local error constant c of the time scheme with these parameters: the principal root
/// R(z) of the step on y' = lambda y (z = lambda dt) is e^z + c z^3 + O(z^4). 1/12 when
/// at = bt = gt = 1/2.
double local_error_constant(const AlphaParameters& alpha);

/// Per group the largest Euclidean norm over the nodes given of the error estimate and of the
/// value (position, orientation: the displacement since the start; u, omega, kappa: the new
/// level). A rank's share: reduce by max.
struct TimeErrorParts {
  GroupValues error{}, size{};
  void include(int group, const Vec3& estimate, const Vec3& value);
};

/// The accepted levels before a step (level n, the step's start, and the two before it) with
/// the lengths of the steps between them (h1 = t_n - t_{n-1}, h2 = t_{n-1} - t_{n-2}), and
/// each node's displacement and rotation since the start (trapezoidal in time on v and w).
struct LevelHistory {
  std::vector<NodeLevel> y0, y1, y2;
  std::vector<Vec3> displacement, rotation;
  double h1 = 0.0, h2 = 0.0;
  int levels = 0;  ///< how many of y0, y1, y2 hold accepted levels (0..3)
  /// The first level (displacements zero).
  void start(std::vector<NodeLevel> y);
  /// After an accepted step of length h from level n to `y_new`: shift the levels.
  void push(std::vector<NodeLevel> y_new, double h);
};

/// The predictor's weights: y_pred = w0 y0 + w1 y1 + w2 y2 at t_n + h (quadratic
/// extrapolation), and the state estimate's factor c h^3 / K.
struct ExtrapolationWeights {
  double w0 = 0.0, w1 = 0.0, w2 = 0.0, factor = 0.0;
};
ExtrapolationWeights extrapolation_weights(double h, double h1, double h2, double c);

/// The estimate's parts for the nodes' new levels (same order as the history's) after a step
/// of h. Needs history.levels == 3.
TimeErrorParts extrapolation_error(const std::vector<NodeLevel>& y_new, const LevelHistory& history, double h,
                                   double c);
/// The same by step doubling from history.y0: `full` one step of h, `mid` and `half` the two
/// steps of h / 2 (kept).
TimeErrorParts doubling_error(const std::vector<NodeLevel>& full, const std::vector<NodeLevel>& mid,
                              const std::vector<NodeLevel>& half, const LevelHistory& history, double h);

/// The weighted error norm of (reduced) parts over the groups `controlled`: the largest of
/// error / (absolute[g] + relative * max(size[g], peak[g], floor[g])); a group with a zero
/// error counts 0.
struct ErrorWeights {
  double relative = 0.0;
  GroupValues absolute{}, floor{};
  std::array<bool, kErrorGroups> controlled{};
};
double weighted_error(const TimeErrorParts& parts, const GroupValues& peak, const ErrorWeights& w);

/// The floors of the relative scale: position 1e-3 of the rod's length, orientation 1e-3 rad
/// (a start from rest, where the displacement is zero, is not held to the relative accuracy
/// of an infinitesimal motion); the state groups none (they need an absolute tolerance).
GroupValues scale_floors(double length);

}  // namespace traverse::rod
