#include "traverse/rod/static_kernels.hpp"

#include <stdexcept>

#include "traverse/core/so3.hpp"

namespace traverse::rod {

using so3::hat;

namespace {

LocalBlock block(Eigen::Index row, std::vector<Eigen::Index> cols, int rows) {
  LocalBlock b;
  b.row = row;
  b.residual = VecX::Zero(rows);
  b.cols = std::move(cols);
  b.jac.assign(b.cols.size(), MatX::Zero(rows, 12));
  return b;
}

}  // namespace

Mat3 frame_perturbation(const Vec3& theta) { return -so3::left_jacobian(-theta); }

Mat3 StaticNode::frame() const { return so3::exp(-x.segment<3>(svar::theta)) * Rbar; }

void StaticNode::rebase() {
  Rbar = frame();
  x.segment<3>(svar::theta).setZero();
}

LocalBlock static_cell_block(const StaticModel& m, int j, const StaticNode& prev, const StaticNode& self) {
  const double ds = m.ds();
  LocalBlock b = block(6 + 12 * static_cast<Eigen::Index>(j - 1), {12 * static_cast<Eigen::Index>(j - 1),
                                                                   12 * static_cast<Eigen::Index>(j)}, 12);
  const StaticNode* nd[2] = {&prev, &self};
  // Without gravity no gravity terms are formed (R f_fixed and its frame sensitivity).
  const bool gravity = m.gravity.x() != 0.0 || m.gravity.y() != 0.0 || m.gravity.z() != 0.0;
  const Vec3 f_fixed = m.props.rhoA * m.gravity;
  Mat3 R[2], D[2];
  for (int q = 0; q < 2; ++q) {
    R[q] = nd[q]->frame();
    D[q] = frame_perturbation(nd[q]->x.segment<3>(svar::theta));
  }
  auto& res = b.residual;
  const double sgn[2] = {-1.0, 1.0};  // difference (self - prev)
  for (int q = 0; q < 2; ++q) {
    const Vec12& x = nd[q]->x;
    auto& J = b.jac[q];
    const Vec3 k = x.segment<3>(svar::kappa), n = x.segment<3>(svar::n);
    const Vec3 mm = m.props.K.cwiseProduct(k - m.props.kappa0);
    // The strain v = e3 + C n of a rod that strains (at rest: no strain rate), e3 otherwise.
    const bool compliant = m.props.compliant();
    const Vec3 v = compliant ? m.props.strain(n, Vec3::Zero()) : Vec3::UnitZ();
    const Vec3 t = R[q].transpose() * v;
    // Force balance.
    if (gravity) {
      const Vec3 fb = R[q] * f_fixed;
      res.segment<3>(0) += -sgn[q] * n / ds + 0.5 * (-k.cross(n) - fb);
      J.block<3, 3>(0, svar::theta) += 0.5 * hat(fb) * D[q];
    } else {
      res.segment<3>(0) += -sgn[q] * n / ds + 0.5 * (-k.cross(n));
    }
    J.block<3, 3>(0, svar::n) += -sgn[q] / ds * Mat3::Identity() - 0.5 * hat(k);
    J.block<3, 3>(0, svar::kappa) += 0.5 * hat(n);
    // Moment balance.
    res.segment<3>(3) += -sgn[q] * mm / ds + 0.5 * (-k.cross(mm) - v.cross(n));
    J.block<3, 3>(3, svar::kappa) += -sgn[q] / ds * Mat3(m.props.K.asDiagonal()) +
                                      0.5 * (-hat(k) * m.props.K.asDiagonal() + hat(mm));
    J.block<3, 3>(3, svar::n) += -0.5 * hat(v);
    if (compliant) J.block<3, 3>(3, svar::n) += 0.5 * hat(n) * m.props.C.asDiagonal();
    // Frame follows the curvature (log part added below).
    res.segment<3>(6) += 0.5 * k;
    J.block<3, 3>(6, svar::kappa) += 0.5 * Mat3::Identity();
    // Centreline.
    res.segment<3>(9) += sgn[q] * x.segment<3>(svar::r) / ds - 0.5 * t;
    J.block<3, 3>(9, svar::r) += sgn[q] / ds * Mat3::Identity();
    J.block<3, 3>(9, svar::theta) += -0.5 * R[q].transpose() * hat(v) * D[q];
    if (compliant) J.block<3, 3>(9, svar::n) += -0.5 * R[q].transpose() * m.props.C.asDiagonal();
  }
  const Mat3 Q = R[1] * R[0].transpose();
  const Vec3 phi = so3::log(Q);
  const Mat3 Jinv = so3::left_jacobian(phi).inverse();
  res.segment<3>(6) += phi / ds;
  b.jac[1].block<3, 3>(6, svar::theta) += Jinv * D[1] / ds;
  b.jac[0].block<3, 3>(6, svar::theta) += -Jinv * Q * D[0] / ds;
  // Point forces: the interior nodes' shares as load densities (PointLoadWeights), as the
  // dynamic cell applies them; the end nodes' shares are in the end rows.
  for (const auto& P : m.point_forces) {
    const PointLoadWeights W = point_load_weights(P.sigma, m.num_cells, ds);
    for (int q = 0; q < 2; ++q) {
      const double w = W.at(j - 1 + q);
      if (w == 0.0) continue;
      const Vec3 Fb = R[q] * P.force;
      res.segment<3>(0) -= 0.5 * w / ds * Fb;
      b.jac[q].block<3, 3>(0, svar::theta) += 0.5 * w / ds * hat(Fb) * D[q];
    }
  }
  return b;
}

LocalBlock static_mass_block(const StaticModel& m, int j, const StaticNode& prev, const StaticNode& self) {
  LocalBlock b = block(6 + 12 * static_cast<Eigen::Index>(j - 1), {12 * static_cast<Eigen::Index>(j - 1),
                                                                   12 * static_cast<Eigen::Index>(j)}, 12);
  const StaticNode* nd[2] = {&prev, &self};
  for (int q = 0; q < 2; ++q) {
    b.jac[q].block<3, 3>(0, svar::r) = 0.5 * m.props.rhoA * nd[q]->frame();
    b.jac[q].block<3, 3>(3, svar::theta) =
        -0.5 * Mat3(m.props.rhoI.asDiagonal()) * frame_perturbation(nd[q]->x.segment<3>(svar::theta));
  }
  return b;
}

Vec3 static_end_point_force(const StaticModel& m, bool right) {
  Vec3 F = Vec3::Zero();
  for (const auto& P : m.point_forces)
    F += point_load_weights(P.sigma, m.num_cells, m.ds()).share(right ? m.num_cells : 0) * P.force;
  return F;
}

LocalBlock static_left_block(const StaticModel& m, const StaticNode& node) {
  LocalBlock b = block(0, {0}, 6);
  static_end_rows(m, m.left, node, -1.0, b);
  return b;
}

LocalBlock static_right_block(const StaticModel& m, const StaticNode& node) {
  LocalBlock b = block(12 * static_cast<Eigen::Index>(m.num_cells) + 6, {12 * static_cast<Eigen::Index>(m.num_cells)}, 6);
  static_end_rows(m, m.right, node, 1.0, b);
  return b;
}

std::vector<StaticNode> straight_static_state(const StaticModel& m, const Vec3& r0, const Mat3& R0) {
  return straight_static_nodes(m, 0, m.num_cells + 1, r0, R0);
}

std::vector<StaticNode> straight_static_nodes(const StaticModel& m, int first, int count, const Vec3& r0,
                                              const Mat3& R0) {
  if (first < 0 || count < 0 || first + count > m.num_cells + 1)
    throw std::invalid_argument("straight_static_nodes: nodes outside 0.." + std::to_string(m.num_cells));
  std::vector<StaticNode> nodes(static_cast<size_t>(count));
  const Vec3 t = R0.transpose() * Vec3::UnitZ();
  for (int k = 0; k < count; ++k) {
    auto& nd = nodes[static_cast<size_t>(k)];
    nd.Rbar = R0;
    nd.x.segment<3>(svar::r) = r0 + t * ((first + k) * m.ds());
  }
  return nodes;
}

RodState dynamic_state_from_static(const StaticModel& m, const std::vector<StaticNode>& nodes) {
  RodState s;
  s.t = 0.0;
  s.ds = m.ds();
  s.nodes = dynamic_nodes_from_static(m, nodes, 0, 0, static_cast<int>(nodes.size()));
  return s;
}

std::vector<RodNode> dynamic_nodes_from_static(const StaticModel& m, const std::vector<StaticNode>& nodes, int first,
                                               int from, int count) {
  const int N = m.num_cells, held = static_cast<int>(nodes.size());
  // Node j needs j - 1 and j + 1 (j - 2 or j + 2 at the ends, N = 1 aside).
  auto needs = [&](int j) { return std::pair<int, int>{std::max(0, j == N ? j - 2 : j - 1), std::min(N, j == 0 ? 2 : j + 1)}; };
  if (count > 0 && (needs(from).first < first || std::min(N, needs(from + count - 1).second) >= first + held ||
                    from < 0 || from + count > N + 1))
    throw std::invalid_argument("dynamic_nodes_from_static: the static nodes held do not cover the neighbours needed");
  const double ds = m.ds();
  std::vector<Vec12> y(nodes.size());
  for (size_t k = 0; k < nodes.size(); ++k) {
    y[k].setZero();
    y[k].segment<3>(var::kappa) = nodes[k].x.segment<3>(svar::kappa);
    y[k].segment<3>(var::n) = nodes[k].x.segment<3>(svar::n);
  }
  auto Y = [&](int j) -> const Vec12& { return y[static_cast<size_t>(j - first)]; };
  std::vector<RodNode> out(static_cast<size_t>(count));
  for (int i = 0; i < count; ++i) {
    const int j = from + i;
    RodNode& d = out[static_cast<size_t>(i)];
    d.R = nodes[static_cast<size_t>(j - first)].frame();
    d.y = Y(j);
    if (N == 1) d.ys = (Y(1) - Y(0)) / ds;
    else if (j == 0) d.ys = (-3.0 * Y(0) + 4.0 * Y(1) - Y(2)) / (2.0 * ds);
    else if (j == N) d.ys = (3.0 * Y(N) - 4.0 * Y(N - 1) + Y(N - 2)) / (2.0 * ds);
    else d.ys = (Y(j + 1) - Y(j - 1)) / (2.0 * ds);
  }
  return out;
}

}  // namespace traverse::rod
