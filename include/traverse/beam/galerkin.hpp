#pragma once
// Galerkin (modal) matrices of a beam by element-wise Gauss-Legendre quadrature.
#include <functional>
#include <vector>

#include "traverse/beam/mode_set.hpp"

namespace traverse::beam {

/// Section property as a function of the axial position x [m].
using SectionFunction = std::function<double(double)>;

/// Mb = int rhoA Phi Phi^T dx [kg], Kb = int EI Phi'' Phi''^T dx [N/m],
/// Pb = g int rhoA Phi dx [N] (self weight; enters the equation as -Pb).
struct GalerkinMatrices {
  MatX Mb;
  MatX Kb;
  VecX Pb;
};

/// Uniform node set x_j = j L / elements, j = 0..elements.
std::vector<double> uniform_nodes(double length, int elements);

/// Assemble the modal matrices over the node set `nodes` (x_0 = 0 < ... < x_N = L, given by
/// the caller) with `gauss_points` Gauss-Legendre points per element. rhoA(x) [kg/m],
/// EI(x) [N m^2], g [m/s^2]. The matrices are symmetrised exactly.
GalerkinMatrices assemble_galerkin(const ModeSet& modes, const std::vector<double>& nodes,
                                   const SectionFunction& rhoA, const SectionFunction& EI,
                                   double g, int gauss_points = 8);

/// The floors of the modal scales of adaptive steps (docs/adaptive.md "Beam module"), so that a
/// start from rest is not held to the relative accuracy of an infinitesimal motion: Y, 1e-3 of
/// the largest static modal response to the self weight and a force `point_load` [N] at
/// midspan; V, that times the first modal frequency.
struct ModalFloors {
  double Y = 0.0, V = 0.0;
};
ModalFloors modal_scale_floors(const GalerkinMatrices& m, const ModeSet& modes, double length, double point_load);

}  // namespace traverse::beam
