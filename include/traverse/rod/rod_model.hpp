#pragma once
// A discretised rod problem: section, scheme parameters, grid, end conditions, loads, and
// the layout of the global unknown vector and equation rows.
#include <Eigen/Core>

#include "traverse/rod/alpha_parameters.hpp"
#include "traverse/rod/end_condition.hpp"
#include "traverse/rod/rod_loads.hpp"
#include "traverse/rod/rod_properties.hpp"

namespace traverse::rod {

/// Global layout (N cells, nodes 0..N).
///
/// Unknowns: node j owns the contiguous block [p j, p (j+1)), p = unknowns_per_node():
///   box scheme (gs = bs = 1/2): p = 12, x_j = y_j = (u, omega, kappa, n) at the new level;
///   carried ys:                 p = 24, x_j = (y_j, ys_j).
///
/// Rows, box scheme (12 (N+1) in all):
///   [0, 6)                     left end condition        (owned by node 0)
///   [6 + 12 (j-1), 6 + 12 j)   cell (j-1, j), j = 1..N  (owned by node j)
///   [6 + 12 N, 12 (N+1))       right end condition       (owned by node N)
/// Rows, carried ys (24 (N+1) in all):
///   [0, 6)                     left end condition        (owned by node 0)
///   [6, 18)                    PDE collocated at node 0  (owned by node 0)
///   [18 + 24 (j-1), +12)       cell (j-1, j) PDE         (owned by node j)
///   [18 + 24 (j-1) + 12, +12)  cell (j-1, j) ys recursion (owned by node j)
///   [18 + 24 N, 24 (N+1))      right end condition       (owned by node N)
/// So the rows owned by node j are contiguous and a node's rows need only its own unknowns
/// and those of node j-1: the Jacobian is block lower-bidiagonal by node (plus the
/// end-condition rows on the diagonal blocks).
struct RodModel {
  RodProperties props;
  AlphaParameters alpha;
  int num_cells = 1;     ///< N
  double length = 1.0;   ///< L [m]; ds = L / N
  EndCondition left, right;
  RodLoads loads;

  double ds() const { return length / num_cells; }
  bool carries_ys() const { return !alpha.box_in_space(); }
  int unknowns_per_node() const { return carries_ys() ? 24 : 12; }
  Eigen::Index num_unknowns() const {
    return static_cast<Eigen::Index>(unknowns_per_node()) * (num_cells + 1);
  }
  Eigen::Index node_col(int j) const {
    return static_cast<Eigen::Index>(unknowns_per_node()) * j;
  }
  Eigen::Index left_row() const { return 0; }
  Eigen::Index collocation_row() const { return 6; }  ///< carried ys only
  Eigen::Index cell_row(int j) const {
    return carries_ys() ? 18 + 24 * static_cast<Eigen::Index>(j - 1)
                        : 6 + 12 * static_cast<Eigen::Index>(j - 1);
  }
  /// Rows of cell j: 12 (box) or 24 (PDE then recursion).
  int cell_rows() const { return carries_ys() ? 24 : 12; }
  Eigen::Index right_row() const { return cell_row(num_cells + 1); }
  /// First row and number of rows owned by node j (see above).
  Eigen::Index node_first_row(int j) const { return j == 0 ? 0 : cell_row(j); }
  int node_row_count(int j) const;
};

}  // namespace traverse::rod
