#include "traverse/beam/modal_damping.hpp"

#include <cmath>
#include <stdexcept>
#include <string>

namespace traverse::beam {

namespace {
void check(const ModalDamping& d, Eigen::Index n) {
  if (d.kind == ModalDamping::Kind::Ratios) {
    const auto k = static_cast<Eigen::Index>(d.ratios.size());
    if (k != 1 && k != n)
      throw std::invalid_argument("modal damping: " + std::to_string(k) + " ratios for " + std::to_string(n) +
                                  " modes (expected one, or one per mode)");
    for (const double z : d.ratios)
      if (!(z >= 0.0) || !std::isfinite(z)) throw std::invalid_argument("modal damping: ratios must be >= 0");
  }
  if (d.kind == ModalDamping::Kind::Rayleigh && (!(d.mass >= 0.0) || !(d.stiffness >= 0.0)))
    throw std::invalid_argument("modal damping: Rayleigh coefficients must be >= 0");
}
}  // namespace

double modal_damping_ratio(const GalerkinMatrices& m, const ModalDamping& d, Eigen::Index i) {
  check(d, m.Mb.rows());
  const double omega = std::sqrt(m.Kb(i, i) / m.Mb(i, i));
  switch (d.kind) {
    case ModalDamping::Kind::None: return 0.0;
    case ModalDamping::Kind::Ratios: return d.ratios.size() == 1 ? d.ratios[0] : d.ratios[static_cast<std::size_t>(i)];
    case ModalDamping::Kind::Rayleigh: return d.mass / (2.0 * omega) + d.stiffness * omega / 2.0;
    default: throw std::invalid_argument("modal damping: unknown kind");
  }
}

MatX modal_damping_matrix(const GalerkinMatrices& m, const ModalDamping& d) {
  const Eigen::Index n = m.Mb.rows();
  check(d, n);
  if (d.kind == ModalDamping::Kind::Rayleigh) return d.mass * m.Mb + d.stiffness * m.Kb;
  MatX C = MatX::Zero(n, n);
  if (d.kind == ModalDamping::Kind::None) return C;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double omega = std::sqrt(m.Kb(i, i) / m.Mb(i, i));
    C(i, i) = 2.0 * modal_damping_ratio(m, d, i) * omega * m.Mb(i, i);
  }
  return C;
}

}  // namespace traverse::beam
