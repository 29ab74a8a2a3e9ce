// Static form of the rod: exact Jacobian and parameter derivatives, and equilibria against
// closed forms, solved as the static initial state of a dynamic run is (load steps of NOX
// Newton solves over the ranks, solver/static_start.hpp). Runs on 1 and 2 ranks.
#include <gtest/gtest.h>

#include <Tpetra_Core.hpp>

#include <cmath>
#include <random>

#include "traverse/core/so3.hpp"
#include "traverse/rod/static_problem.hpp"
#include "traverse/solver/static_start.hpp"

using namespace traverse;
using namespace traverse::rod;

namespace {

StaticModel scene_model(int cells) {
  StaticModel m;
  m.props = RodProperties::scene_rod();
  m.num_cells = cells;
  m.length = 1.0;
  m.left.type = EndCondition::Type::clamped;
  m.right.type = EndCondition::Type::free;
  m.right.position = Vec3(0, 0, 1);
  return m;
}

// The equilibrium under m's loads from the straight state by the static start over the
// test's ranks, all nodes on every rank (a halo of the whole rod).
std::vector<StaticNode> equilibrium(const StaticModel& m) {
  const solver::StaticStart st = solver::solve_static_start(m, Tpetra::getDefaultComm(), {}, m.num_cells);
  EXPECT_TRUE(st.report.converged) << st.report.message;
  if (st.report.converged) {
    EXPECT_EQ(st.nodes.size(), static_cast<size_t>(m.num_cells + 1));
  }
  return st.nodes;
}

bool root() { return Tpetra::getDefaultComm()->getRank() == 0; }

std::vector<StaticNode> random_nodes(const StaticModel& m, std::mt19937& g) {
  std::uniform_real_distribution<double> d(-1.0, 1.0);
  auto nodes = straight_static_state(m);
  for (auto& n : nodes) {
    for (int i = 0; i < 12; ++i) n.x(i) += (i >= svar::n ? 0.5 : 0.3) * d(g);
    n.Rbar = so3::exp(Vec3(d(g), d(g), d(g)));
  }
  return nodes;
}

// Central differences of a block's residual with respect to its nodes' unknowns.
void check_jacobian(std::vector<StaticNode> nodes,
                    const std::function<LocalBlock(const std::vector<StaticNode>&)>& f, const char* what) {
  const LocalBlock b = f(nodes);
  double worst = 0.0;
  for (size_t k = 0; k < b.cols.size(); ++k) {
    const size_t node = static_cast<size_t>(b.cols[k] / 12);
    for (int c = 0; c < 12; ++c) {
      const double h = 1e-6;
      auto plus = nodes, minus = nodes;
      plus[node].x(c) += h;
      minus[node].x(c) -= h;
      const VecX fd = (f(plus).residual - f(minus).residual) / (2 * h);
      const VecX an = b.jac[k].col(c);
      const double scale = std::max(1.0, an.cwiseAbs().maxCoeff());
      worst = std::max(worst, (fd - an).cwiseAbs().maxCoeff() / scale);
    }
  }
  if (root()) std::cout << "  " << what << ": max relative Jacobian error " << worst << "\n";
  EXPECT_LT(worst, 1e-7) << what;
}

}  // namespace

TEST(RodStatics, JacobianMatchesCentralDifferences) {
  std::mt19937 g(7);
  using T = EndCondition::Type;
  // The inextensible rod and the rods that strain (compliances large enough that C n shows).
  for (RodStrain strain : {RodStrain::inextensible, RodStrain::extensible, RodStrain::shearable}) {
    for (T lt : {T::clamped, T::pinned, T::sliding, T::free}) {
      StaticModel m = scene_model(4);
      m.props.C = RodProperties::compliance(strain, 5.0, 2.0);
      m.gravity = Vec3(0, -9.8, 0);
      m.point_forces.push_back({Vec3(0.3, -2.0, 0.1), 0.3});
      m.left.type = lt;
      m.left.axis = Vec3(1, 0.2, 0).normalized();
      m.left.frame = so3::exp(Vec3(0.1, 0.2, -0.3));
      m.left.axial_force = 1.5;
      m.left.end_force = Vec3(0.2, 0.1, -0.4);
      m.right.type = lt == T::free ? T::sliding : T::free;
      m.right.axis = Vec3(0, 0, 1);
      m.right.end_force = Vec3(1, 2, 3);
      auto nodes = random_nodes(m, g);
      check_jacobian(nodes, [&](const std::vector<StaticNode>& n) { return static_cell_block(m, 2, n[1], n[2]); }, "cell");
      check_jacobian(nodes, [&](const std::vector<StaticNode>& n) { return static_left_block(m, n[0]); }, "left end");
      check_jacobian(nodes, [&](const std::vector<StaticNode>& n) { return static_right_block(m, n[4]); }, "right end");
    }
  }
}

TEST(RodStatics, CantileverUnderSelfWeightMatchesBeamTheoryInTheStiffLimit) {
  // q L^4 / (8 EI) tip deflection; the scene rod is soft (sag ~ 0.2 L), so stiffen it 1e4x
  // to stay in the linear range, where the relative nonlinear correction is O((w/L)^2).
  StaticModel m = scene_model(50);
  m.props.K *= 1e4;
  m.gravity = Vec3(0, -9.8, 0);
  const auto nodes = equilibrium(m);
  ASSERT_FALSE(nodes.empty());
  const double q = m.props.rhoA * 9.8, EI = m.props.K(0);
  const double beam = q / (8 * EI);
  const double tip = -nodes.back().x(svar::r + 1);
  if (root()) std::cout << "  tip deflection " << tip << " m, beam theory " << beam << " m, relative difference "
            << (tip - beam) / beam << "\n";
  EXPECT_NEAR(tip, beam, 2e-3 * beam);
  // The clamp carries the weight: n(0) = -(force of the clamp on the rod) = -q L j.
  const Vec3 n0 = nodes.front().frame().transpose() * nodes.front().x.segment<3>(svar::n);
  EXPECT_NEAR(n0.y(), -q * 1.0, 1e-9 * q);
}

TEST(RodStatics, LargeDeflectionCantileverTipLoadMatchesTheElastica) {
  // Tip load P with P L^2 / EI = 1 (Bisshopp & Drucker 1945): vertical tip deflection
  // 0.30172 L, horizontal 0.05643 L (published to 4-5 digits). Order 2 in ds.
  double errs[3];
  const int cells[3] = {20, 40, 80};
  for (int c = 0; c < 3; ++c) {
    StaticModel m = scene_model(cells[c]);
    const double EI = m.props.K(0);
    m.right.end_force = Vec3(0, -EI, 0);
    const auto nodes = equilibrium(m);
    ASSERT_FALSE(nodes.empty());
    const Vec3 tip = nodes.back().x.segment<3>(svar::r);
    errs[c] = -tip.y();
    if (root()) std::cout << "  N = " << cells[c] << ": tip (x, y, z) = " << tip.transpose() << "\n";
    EXPECT_NEAR(-tip.y(), 0.30172, 2e-3);
    EXPECT_NEAR(1.0 - tip.z(), 0.05643, 2e-3);
    EXPECT_NEAR(tip.x(), 0.0, 1e-12);
  }
  const double order = std::log2((errs[0] - errs[1]) / (errs[1] - errs[2]));
  if (root()) std::cout << "  observed order in ds of the tip deflection: " << order << "\n";
  EXPECT_NEAR(order, 2.0, 0.1);
}

TEST(RodStatics, HangingCableSagMatchesTheClampedClampedBeamInTheStiffLimit) {
  // Left clamped at the origin, right clamped and sliding along k: midspan sag q L^4/(384 EI)
  // in the stiff (linear) limit, reached at order 2 in ds.
  double err[3];
  const int cells[3] = {20, 40, 80};
  for (int c = 0; c < 3; ++c) {
    StaticModel m = scene_model(cells[c]);
    m.props.K *= 1e3;
    m.right.type = EndCondition::Type::sliding;
    m.right.axis = Vec3(0, 0, 1);
    m.gravity = Vec3(0, -9.8, 0);
    const auto nodes = equilibrium(m);
    ASSERT_FALSE(nodes.empty());
    const double q = m.props.rhoA * 9.8, EI = m.props.K(0);
    const double beam = q / (384 * EI);
    const double mid = -nodes[static_cast<size_t>(cells[c] / 2)].x(svar::r + 1);
    err[c] = (mid - beam) / beam;
    if (root()) std::cout << "  N = " << cells[c] << ": midspan sag " << mid << " m, beam theory " << beam
              << " m, relative difference " << err[c] << "\n";
    // Sliding end: no axial force.
    const Vec3 nL = nodes.back().frame().transpose() * nodes.back().x.segment<3>(svar::n);
    EXPECT_NEAR(nL.z(), 0.0, 1e-9);
  }
  EXPECT_LT(std::abs(err[2]), 1e-3);
  const double order = std::log2(err[0] / err[1]), order2 = std::log2(err[1] / err[2]);
  if (root()) std::cout << "  observed orders in ds: " << order << ", " << order2 << "\n";
  EXPECT_NEAR(order2, 2.0, 0.1);
}

TEST(RodStatics, StaticStateIsConsistentWithTheDynamicCurvatureFrame) {
  StaticModel m = scene_model(30);
  m.gravity = Vec3(0, -9.8, 0);
  const auto nodes = equilibrium(m);
  ASSERT_FALSE(nodes.empty());
  const RodState s = dynamic_state_from_static(m, nodes);
  for (size_t j = 1; j < nodes.size(); ++j) {
    const Vec3 kb = 0.5 * (s.nodes[j - 1].y.segment<3>(var::kappa) + s.nodes[j].y.segment<3>(var::kappa));
    const Mat3 expected = so3::exp(-m.ds() * kb) * s.nodes[j - 1].R;
    EXPECT_LT((expected - s.nodes[j].R).cwiseAbs().maxCoeff(), 1e-10);
  }
}

// A rank's piece of the dynamic initial state (its nodes and ghosts, from the static nodes it
// holds with their neighbours) is the same piece of the whole rod's, to the bit; a piece that
// lacks a neighbour is refused.
TEST(RodStatics, DynamicStatePiecesEqualTheWholeState) {
  StaticModel m = scene_model(12);
  m.gravity = Vec3(0, -9.8, 0);
  const auto nodes = equilibrium(m);
  ASSERT_FALSE(nodes.empty());
  const RodState whole = dynamic_state_from_static(m, nodes);
  const int N = m.num_cells;
  for (const auto& [from, count] : std::vector<std::pair<int, int>>{{0, 2}, {0, 5}, {4, 4}, {9, 4}, {11, 2}, {0, 13}}) {
    const int end = from + count - 1;  // the neighbours needed: one each side, two at the rod's ends
    const int first = end == N ? std::min(std::max(0, from - 1), N - 2) : std::max(0, from - 1);
    const int last = from == 0 ? std::max(std::min(N, end + 1), 2) : std::min(N, end + 1);
    const std::vector<StaticNode> held(nodes.begin() + first, nodes.begin() + last + 1);
    const std::vector<RodNode> piece = dynamic_nodes_from_static(m, held, first, from, count);
    ASSERT_EQ(piece.size(), static_cast<size_t>(count));
    for (int i = 0; i < count; ++i) {
      const RodNode& a = piece[static_cast<size_t>(i)];
      const RodNode& b = whole.nodes[static_cast<size_t>(from + i)];
      EXPECT_TRUE(a.y == b.y && a.ys == b.ys && a.R == b.R && a.yt == b.yt) << "node " << from + i;
    }
  }
  const std::vector<StaticNode> interior(nodes.begin() + 4, nodes.begin() + 8);  // nodes 4..7
  EXPECT_THROW(dynamic_nodes_from_static(m, interior, 4, 4, 3), std::invalid_argument);  // node 4 needs 3
  EXPECT_NO_THROW(dynamic_nodes_from_static(m, interior, 4, 5, 2));
  const std::vector<StaticNode> left(nodes.begin(), nodes.begin() + 2);  // nodes 0, 1: node 0 needs 2
  EXPECT_THROW(dynamic_nodes_from_static(m, left, 0, 0, 1), std::invalid_argument);
}

// dF/dp of every continuation parameter, for each right-end type, against central
// differences of the cell and end residuals (the residual is affine in each parameter within
// a cell, so the differences are exact up to rounding). The load sits inside an interior
// cell, inside each end cell (part of it then acts in the end's rows) and, for the load
// position, on an interior node, where the shares are kinked: there the derivative is the
// mean of the two cells' slopes, which the central difference gives.
TEST(RodStatics, ParameterDerivativesMatchDifferences) {
  std::mt19937 g(7);
  using T = EndCondition::Type;
  double worst = 0.0;
  for (T right : {T::free, T::sliding, T::roller, T::clamped, T::pinned}) {
    StaticProblem pr;
    pr.base = scene_model(8);
    pr.base.right.type = right;
    pr.base.right.axis = right == T::sliding ? Vec3(0.2, 0.1, 1.0).normalized() : Vec3::UnitX();
    pr.base.left.type = right == T::free ? T::sliding : T::free;  // ends whose rows read the force
    pr.base.left.axis = Vec3(0.2, 0.1, 1.0).normalized();
    pr.base.right.slide_axis = Vec3(0.0, 0.3, 1.0).normalized();
    pr.end_load_direction = Vec3(0.1, -0.2, -1.0).normalized();
    pr.end_position_axis = Vec3(0.3, 0.2, 1.0).normalized();
    pr.has_point_load = true;
    pr.load_direction = Vec3(0.2, -1.0, 0.1).normalized();
    pr.values = {0.7, 0.95, 1.3, 0.4 + 0.3 * 0.125, 2.0};  // load 30 % into cell 4
    const auto nodes = random_nodes(pr.base, g);
    for (int q = 0; q < num_static_parameters; ++q) {
      const auto ip = static_cast<StaticParameter>(q);
      for (double sigma : {pr.values[3], 0.0375, 0.925, 0.5}) {  // cells 4, 1 and 8, then on node 4
        if (sigma == 0.5 && ip != StaticParameter::load_position) continue;
        auto v = pr.values;
        v[3] = sigma;
        const double h = 1e-4;
        auto vp = v, vm = v;
        vp[static_cast<size_t>(q)] += h;
        vm[static_cast<size_t>(q)] -= h;
        const double width = 2.0 * h;
        const int N = pr.base.num_cells;
        for (int j = 1; j <= N; ++j) {
          const VecX fd = (static_cell_block(pr.model(vp), j, nodes[j - 1], nodes[j]).residual -
                           static_cell_block(pr.model(vm), j, nodes[j - 1], nodes[j]).residual) / width;
          const VecX an = static_cell_dfdp(pr, v, ip, j, nodes[j - 1], nodes[j]);
          worst = std::max(worst, (fd - an).cwiseAbs().maxCoeff() / std::max(1.0, an.cwiseAbs().maxCoeff()));
        }
        const VecX fd = (static_right_block(pr.model(vp), nodes[N]).residual -
                         static_right_block(pr.model(vm), nodes[N]).residual) / width;
        const VecX an = static_end_dfdp(pr, v, ip, nodes[N], true);
        worst = std::max(worst, (fd - an).cwiseAbs().maxCoeff() / std::max(1.0, an.cwiseAbs().maxCoeff()));
        const VecX fl = (static_left_block(pr.model(vp), nodes[0]).residual -
                         static_left_block(pr.model(vm), nodes[0]).residual) / width;
        const VecX al = static_end_dfdp(pr, v, ip, nodes[0], false);
        worst = std::max(worst, (fl - al).cwiseAbs().maxCoeff() / std::max(1.0, al.cwiseAbs().maxCoeff()));
      }
    }
  }
  if (root()) std::cout << "  max relative dF/dp error (5 end types x 5 parameters) " << worst << "\n";
  EXPECT_LT(worst, 1e-8);
}
