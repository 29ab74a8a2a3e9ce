#include "traverse/beam/galerkin.hpp"

#include <cmath>
#include <stdexcept>

#include "traverse/beam/gauss_legendre.hpp"

namespace traverse::beam {

std::vector<double> uniform_nodes(double length, int elements) {
  if (elements < 1 || !(length > 0)) throw std::invalid_argument("uniform_nodes: bad arguments");
  std::vector<double> x(static_cast<std::size_t>(elements) + 1);
  for (int j = 0; j <= elements; ++j) x[static_cast<std::size_t>(j)] = length * j / elements;
  x.back() = length;
  return x;
}

GalerkinMatrices assemble_galerkin(const ModeSet& modes, const std::vector<double>& nodes,
                                   const SectionFunction& rhoA, const SectionFunction& EI,
                                   double g, int gauss_points) {
  if (nodes.size() < 2) throw std::invalid_argument("assemble_galerkin: need at least 2 nodes");
  const double L = modes.length();
  if (std::abs(nodes.front()) > 1e-12 * L || std::abs(nodes.back() - L) > 1e-12 * L)
    throw std::invalid_argument("assemble_galerkin: nodes must span [0, L]");
  for (std::size_t j = 1; j < nodes.size(); ++j)
    if (!(nodes[j] > nodes[j - 1])) throw std::invalid_argument("assemble_galerkin: nodes must increase");
  if (!rhoA || !EI) throw std::invalid_argument("assemble_galerkin: section functions missing");

  const Eigen::Index n = modes.size();
  const GaussLegendre rule(gauss_points);
  GalerkinMatrices m;
  m.Mb = MatX::Zero(n, n);
  m.Kb = MatX::Zero(n, n);
  m.Pb = VecX::Zero(n);
  VecX phi(n), dphi(n), ddphi(n);
  for (std::size_t e = 0; e + 1 < nodes.size(); ++e) {
    const double a = nodes[e], b = nodes[e + 1], half = 0.5 * (b - a), mid = 0.5 * (a + b);
    for (std::size_t q = 0; q < rule.points.size(); ++q) {
      const double x = mid + half * rule.points[q], w = half * rule.weights[q];
      modes.evaluate(x, phi, dphi, ddphi);
      const double ra = rhoA(x) * w, ei = EI(x) * w;
      m.Mb.selfadjointView<Eigen::Lower>().rankUpdate(phi, ra);
      m.Kb.selfadjointView<Eigen::Lower>().rankUpdate(ddphi, ei);
      m.Pb.noalias() += (g * ra) * phi;
    }
  }
  m.Mb = m.Mb.selfadjointView<Eigen::Lower>();
  m.Kb = m.Kb.selfadjointView<Eigen::Lower>();
  return m;
}

ModalFloors modal_scale_floors(const GalerkinMatrices& m, const ModeSet& modes, double length, double point_load) {
  const Eigen::Index n = modes.size();
  VecX phi(n), dphi(n), ddphi(n);
  modes.evaluate(0.5 * length, phi, dphi, ddphi);
  const auto K = m.Kb.ldlt();
  ModalFloors f;
  f.Y = 1e-3 * (K.solve(m.Pb).lpNorm<Eigen::Infinity>() + point_load * K.solve(phi).lpNorm<Eigen::Infinity>());
  f.V = f.Y * std::sqrt(m.Kb(0, 0) / m.Mb(0, 0));
  return f;
}

}  // namespace traverse::beam
