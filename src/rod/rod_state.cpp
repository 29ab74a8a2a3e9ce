#include "traverse/rod/rod_state.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "traverse/core/so3.hpp"

namespace traverse::rod {

void pack_node(const RodNode& nd, double* o) {
  for (int i = 0; i < 12; ++i) o[i] = nd.y(i);
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 3; ++c) o[12 + 3 * i + c] = nd.R(i, c);
  for (int i = 0; i < 12; ++i) o[21 + i] = nd.yt(i);
  for (int i = 0; i < 12; ++i) o[33 + i] = nd.ys(i);
  for (int i = 0; i < 12; ++i) o[45 + i] = nd.yv(i);
  for (int i = 0; i < 12; ++i) o[57 + i] = nd.yg(i);
  for (int i = 0; i < 3; ++i) o[69 + i] = nd.kst(i);
}

RodNode unpack_node(const double* o) {
  RodNode nd;
  for (int i = 0; i < 12; ++i) nd.y(i) = o[i];
  for (int i = 0; i < 3; ++i)
    for (int c = 0; c < 3; ++c) nd.R(i, c) = o[12 + 3 * i + c];
  for (int i = 0; i < 12; ++i) nd.yt(i) = o[21 + i];
  for (int i = 0; i < 12; ++i) nd.ys(i) = o[33 + i];
  for (int i = 0; i < 12; ++i) nd.yv(i) = o[45 + i];
  for (int i = 0; i < 12; ++i) nd.yg(i) = o[57 + i];
  for (int i = 0; i < 3; ++i) nd.kst(i) = o[69 + i];
  return nd;
}

RodState straight_rest_state(int num_cells, double length, const Mat3& R0) {
  if (num_cells < 1 || !(length > 0.0)) throw std::invalid_argument("straight_rest_state: bad grid");
  RodState s;
  s.t = 0.0;
  s.ds = length / num_cells;
  s.nodes.assign(static_cast<size_t>(num_cells) + 1, RodNode{});
  for (auto& n : s.nodes) n.R = R0;
  return s;
}

RodState state_from_curvature(int num_cells, double length,
                              const std::function<Vec3(double)>& kappa, const Mat3& R0) {
  RodState s = straight_rest_state(num_cells, length, R0);
  const int N = num_cells;
  const double ds = s.ds;
  for (int j = 0; j <= N; ++j) s.nodes[j].y.segment<3>(var::kappa) = kappa(j * ds);
  for (int j = 1; j <= N; ++j) {
    const Vec3 km = 0.5 * (s.nodes[j - 1].y.segment<3>(var::kappa) + s.nodes[j].y.segment<3>(var::kappa));
    s.nodes[j].R = so3::exp(-ds * km) * s.nodes[j - 1].R;
  }
  // ys by second-order differences.
  for (int j = 0; j <= N; ++j) {
    if (N == 1) {
      s.nodes[j].ys = (s.nodes[1].y - s.nodes[0].y) / ds;
    } else if (j == 0) {
      s.nodes[j].ys = (-3.0 * s.nodes[0].y + 4.0 * s.nodes[1].y - s.nodes[2].y) / (2.0 * ds);
    } else if (j == N) {
      s.nodes[j].ys = (3.0 * s.nodes[N].y - 4.0 * s.nodes[N - 1].y + s.nodes[N - 2].y) / (2.0 * ds);
    } else {
      s.nodes[j].ys = (s.nodes[j + 1].y - s.nodes[j - 1].y) / (2.0 * ds);
    }
  }
  return s;
}

namespace {
double energy_density(const RodProperties& p, const Vec12& y) {
  const Vec3 u = y.segment<3>(var::u), w = y.segment<3>(var::omega);
  const Vec3 dk = y.segment<3>(var::kappa) - p.kappa0;
  return 0.5 * p.rhoA * u.squaredNorm() + 0.5 * w.dot(p.rhoI.cwiseProduct(w)) +
         0.5 * dk.dot(p.K.cwiseProduct(dk));
}

// The strain energy density 1/2 d . C^-1 d of a strain deviation d = v - e3, over the
// directions the rod strains in.
double strain_energy_density(const RodProperties& p, const Vec3& d) {
  double e = 0.0;
  for (int i = 0; i < 3; ++i)
    if (p.C(i) != 0.0) e += 0.5 * d(i) * d(i) / p.C(i);
  return e;
}
}  // namespace

Vec3 strain_deviation(const RodNode& node, const RodProperties& props) {
  return props.C.cwiseProduct(node.y.segment<3>(var::n)) -
         props.retardation().cwiseProduct(node.yt.segment<3>(var::n));
}

double discrete_energy(const RodState& state, const RodProperties& props) {
  double e = 0.0;
  for (int j = 1; j <= state.num_cells(); ++j)
    e += energy_density(props, 0.5 * (state.nodes[j - 1].y + state.nodes[j].y));
  if (props.compliant())
    for (int j = 1; j <= state.num_cells(); ++j)
      e += strain_energy_density(
          props, 0.5 * (strain_deviation(state.nodes[j - 1], props) + strain_deviation(state.nodes[j], props)));
  return e * state.ds;
}

double nodal_energy(const RodState& state, const RodProperties& props) {
  const int N = state.num_cells();
  double e = 0.0;
  for (int j = 0; j <= N; ++j)
    e += ((j == 0 || j == N) ? 0.5 : 1.0) * energy_density(props, state.nodes[j].y);
  if (props.compliant())
    for (int j = 0; j <= N; ++j)
      e += ((j == 0 || j == N) ? 0.5 : 1.0) * strain_energy_density(props, strain_deviation(state.nodes[j], props));
  return e * state.ds;
}

double discrete_dissipation(const RodState& old_state, const RodState& state, const RodProperties& props) {
  const double dt = state.t - old_state.t;
  auto rates = [&](int j, Vec3& vt, Vec3& kt) {  // secant rates of node j over the step
    vt = (strain_deviation(state.nodes[j], props) - strain_deviation(old_state.nodes[j], props)) / dt;
    kt = (state.nodes[j].y - old_state.nodes[j].y).segment<3>(var::kappa) / dt;
  };
  double d = 0.0;
  Vec3 vp, kp, vc, kc;
  rates(0, vp, kp);
  for (int j = 1; j <= state.num_cells(); ++j) {
    rates(j, vc, kc);
    const Vec3 v = 0.5 * (vp + vc), k = 0.5 * (kp + kc);
    d += v.dot(props.B_se.cwiseProduct(v)) + k.dot(props.B_bt.cwiseProduct(k));  // v = 0 where C = 0
    vp = vc;
    kp = kc;
  }
  return d * state.ds;
}

std::vector<Vec3> centreline_in_space(const RodState& state, const Vec3& r0) {
  std::vector<Vec3> t(state.nodes.size());
  for (size_t j = 0; j < t.size(); ++j) t[j] = tangent(state.nodes[j]);
  return centreline_from(t, state.ds, r0);
}

std::vector<Vec3> centreline_from(const std::vector<Vec3>& tangents, double ds, const Vec3& r_first) {
  std::vector<Vec3> r(tangents.size());
  if (r.empty()) return r;
  r[0] = r_first;
  for (size_t j = 1; j < r.size(); ++j) r[j] = r[j - 1] + 0.5 * ds * (tangents[j - 1] + tangents[j]);
  return r;
}

CentrelinePiece centreline_piece(const std::vector<Vec3>& tangents, int first, double ds, const Vec3& origin) {
  CentrelinePiece p;
  p.first = first;
  p.count = static_cast<int>(tangents.size());
  p.end = origin;
  if (tangents.empty()) return p;
  p.first_tangent = tangents.front();
  p.last_tangent = tangents.back();
  for (size_t j = 1; j < tangents.size(); ++j) p.end = p.end + 0.5 * ds * (tangents[j - 1] + tangents[j]);
  return p;
}

std::vector<Vec3> centreline_starts(const std::vector<CentrelinePiece>& pieces, double ds, const Vec3& r0) {
  std::vector<size_t> order;
  for (size_t i = 0; i < pieces.size(); ++i)
    if (pieces[i].count > 0) order.push_back(i);
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return pieces[a].first < pieces[b].first; });
  std::vector<Vec3> start(pieces.size(), r0);
  int next = 0;  // the node the next piece must start at
  Vec3 r = r0;   // r at the last node of the piece before, then at the first node of this one
  for (size_t k = 0; k < order.size(); ++k) {
    const CentrelinePiece& p = pieces[order[k]];
    if (p.first != next)
      throw std::invalid_argument("centreline_starts: a piece starts at node " + std::to_string(p.first) +
                                  ", expected node " + std::to_string(next));
    if (k > 0) r = r + 0.5 * ds * (pieces[order[k - 1]].last_tangent + p.first_tangent);
    start[order[k]] = r;
    r = k == 0 ? p.end : Vec3(r + p.end);  // the first piece's end is r at its last node
    next = p.first + p.count;
  }
  return start;
}

NodeInterpolation locate_on_nodes(double s, double ds, int num_cells) {
  int j = static_cast<int>(std::floor(s / ds));
  j = std::clamp(j, 0, num_cells - 1);
  return {j, std::clamp(s / ds - j, 0.0, 1.0)};
}

OutputNeeds output_needs(int num_cells, double ds, const std::vector<PointOutput>& points, bool centreline_field) {
  OutputNeeds n;
  n.centreline = centreline_field;
  for (const auto& p : points) n.centreline = n.centreline || p.position;
  for (const auto& p : points) {
    const NodeInterpolation loc = locate_on_nodes(p.s, ds, num_cells);
    n.nodes.push_back(loc.j);
    n.nodes.push_back(loc.j + 1);
  }
  std::sort(n.nodes.begin(), n.nodes.end());
  n.nodes.erase(std::unique(n.nodes.begin(), n.nodes.end()), n.nodes.end());
  return n;
}

std::vector<Vec3> advance_centreline_in_time(const std::vector<Vec3>& r_old,
                                             const RodState& old_state,
                                             const RodState& new_state) {
  const double dt = new_state.t - old_state.t;
  std::vector<Vec3> r(r_old.size());
  for (size_t j = 0; j < r.size(); ++j) {
    const auto& a = old_state.nodes[j];
    const auto& b = new_state.nodes[j];
    r[j] = r_old[j] + 0.5 * dt * (a.R.transpose() * a.y.segment<3>(var::u) +
                                  b.R.transpose() * b.y.segment<3>(var::u));
  }
  return r;
}

}  // namespace traverse::rod
