#pragma once
// The one formula of a cell (j-1, j) of the generalised-alpha box scheme, for D unknowns of y
// per node: the 3D kernel (D = 12, rod_kernels.cpp) and the in-plane kernel of the planar
// path (D = 6, planar.cpp) both evaluate it, each with its own node quantities.
//
//   PDE rows:        Mm A_t + Kk A_s + A_F
//   A_t = (1 - at) ((1 - as) yt_new(j) + as yt_new(j-1)) + at ((1 - as) yt_old(j) + as yt_old(j-1))
//   A_s = (1 - bt) (y_new(j) - y_new(j-1)) / ds + bt (y_old(j) - y_old(j-1)) / ds   (box scheme)
//       = (1 - bt) ((1 - bs) ys_new(j) + bs ys_new(j-1)) + bt (...old...)            (carried ys)
//   A_F = (1 - bt) ((1 - bs) F_new(j) + bs F_new(j-1)) + bt ((1 - bs) F_old(j) + bs F_old(j-1))
//   recursion rows (carried ys): gs ys_new(j) + (1 - gs) ys_new(j-1) - (y_new(j) - y_new(j-1)) / ds
// and its Jacobian with respect to the new unknowns (y, and ys when carried) of both nodes,
// given each node's total derivative dF_new/dy_new (frame rotation included).
#include <Eigen/Dense>

#include "traverse/rod/alpha_parameters.hpp"

namespace traverse::rod {

/// One node's quantities at both levels, as a cell reads them.
template <int D>
struct CellNode {
  using V = Eigen::Matrix<double, D, 1>;
  Eigen::Ref<const V> y_old, yt_old, ys_old, F_old;  ///< old level (ys_old: carried only)
  Eigen::Ref<const V> y_new, ys_new, yt_new, F_new;  ///< new level (ys_new: carried only)
};

/// The cell's residual rows into r (D rows, 2 D with carried ys).
template <int D, class Residual>
void cell_scheme_residual(Residual& r, const AlphaParameters& a, bool carried, double ds,
                          const Eigen::Matrix<double, D, D>& Mm, const Eigen::Matrix<double, D, D>& Kk,
                          const CellNode<D>& prev, const CellNode<D>& cur) {
  using V = Eigen::Matrix<double, D, 1>;
  const V At = (1.0 - a.at) * ((1.0 - a.as) * cur.yt_new + a.as * prev.yt_new) +
               a.at * ((1.0 - a.as) * cur.yt_old + a.as * prev.yt_old);
  V As;
  if (carried) {
    As = (1.0 - a.bt) * ((1.0 - a.bs) * cur.ys_new + a.bs * prev.ys_new) +
         a.bt * ((1.0 - a.bs) * cur.ys_old + a.bs * prev.ys_old);
  } else {
    As = (1.0 - a.bt) * (cur.y_new - prev.y_new) / ds + a.bt * (cur.y_old - prev.y_old) / ds;
  }
  const V AF = (1.0 - a.bt) * ((1.0 - a.bs) * cur.F_new + a.bs * prev.F_new) +
               a.bt * ((1.0 - a.bs) * cur.F_old + a.bs * prev.F_old);
  r.resize(carried ? 2 * D : D);
  r.template head<D>() = Mm * At + Kk * As + AF;
  if (carried) r.template tail<D>() = a.gs * cur.ys_new + (1.0 - a.gs) * prev.ys_new - (cur.y_new - prev.y_new) / ds;
}

/// The cell's Jacobian blocks with respect to node j-1 (Jp) and j (Jc), each sized and zeroed
/// by the caller (D or 2 D square). dFp, dFc: the nodes' dF_new/dy_new.
template <int D, class Block>
void cell_scheme_jacobian(Block& Jp, Block& Jc, const AlphaParameters& a, bool carried, double ds, double dt,
                          const Eigen::Matrix<double, D, D>& Mm, const Eigen::Matrix<double, D, D>& Kk,
                          const Eigen::Matrix<double, D, D>& dFp, const Eigen::Matrix<double, D, D>& dFc) {
  using M = Eigen::Matrix<double, D, D>;
  const double ct = (1.0 - a.at) / (a.gt * dt);
  Jc.template block<D, D>(0, 0) = ct * (1.0 - a.as) * Mm + (1.0 - a.bt) * (1.0 - a.bs) * dFc;
  Jp.template block<D, D>(0, 0) = ct * a.as * Mm + (1.0 - a.bt) * a.bs * dFp;
  if (carried) {
    Jc.template block<D, D>(0, D) = (1.0 - a.bt) * (1.0 - a.bs) * Kk;
    Jp.template block<D, D>(0, D) = (1.0 - a.bt) * a.bs * Kk;
    // Recursion gs ys(j) + (1 - gs) ys(j-1) - (y(j) - y(j-1)) / ds = 0 at the new level.
    Jc.template block<D, D>(D, D) = a.gs * M::Identity();
    Jp.template block<D, D>(D, D) = (1.0 - a.gs) * M::Identity();
    Jc.template block<D, D>(D, 0) = -M::Identity() / ds;
    Jp.template block<D, D>(D, 0) = M::Identity() / ds;
  } else {
    Jc.template block<D, D>(0, 0) += (1.0 - a.bt) / ds * Kk;
    Jp.template block<D, D>(0, 0) -= (1.0 - a.bt) / ds * Kk;
  }
}

}  // namespace traverse::rod
