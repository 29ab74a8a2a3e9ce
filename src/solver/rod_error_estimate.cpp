#include "traverse/solver/rod_error_estimate.hpp"

#include <algorithm>
#include <stdexcept>

#include "traverse/core/comm.hpp"

namespace traverse::solver {

RodErrorEstimate::RodErrorEstimate(const rod::ErrorWeights& weights, const rod::AlphaParameters& alpha, MPI_Comm comm)
    : weights_(weights), c_(rod::local_error_constant(alpha)), comm_(comm) {}

double RodErrorEstimate::reduce(const rod::TimeErrorParts& local) const {
  constexpr int G = rod::kErrorGroups;
  double in[2 * G], out[2 * G];
  for (int g = 0; g < G; ++g) {
    in[g] = local.error[g];
    in[G + g] = local.size[g];
  }
  par::allreduce(in, out, 2 * G, MPI_DOUBLE, MPI_MAX, comm_);
  rod::TimeErrorParts all;
  for (int g = 0; g < G; ++g) {
    all.error[g] = out[g];
    all.size[g] = out[G + g];
  }
  last_sizes_ = all.size;
  return rod::weighted_error(all, peak_, weights_);
}

double RodErrorEstimate::extrapolation_error(const std::vector<rod::NodeLevel>& y_new, double h) const {
  if (!has_history()) throw std::logic_error("RodErrorEstimate: the extrapolation estimate needs three levels");
  return reduce(rod::extrapolation_error(y_new, history_, h, c_));
}

double RodErrorEstimate::doubling_error(const std::vector<rod::NodeLevel>& full, const std::vector<rod::NodeLevel>& mid,
                                        const std::vector<rod::NodeLevel>& half, double h) const {
  return reduce(rod::doubling_error(full, mid, half, history_, h));
}

void RodErrorEstimate::accept(std::vector<rod::NodeLevel> y_new, double h) {
  // The peaks are the sizes of the last estimate (global: reduced by max), so that every rank
  // weighs the error alike.
  for (int g = 0; g < rod::kErrorGroups; ++g) peak_[g] = std::max(peak_[g], last_sizes_[g]);
  history_.push(std::move(y_new), h);
}

void RodErrorEstimate::pack_node(int k, double* out) const {
  const size_t j = static_cast<size_t>(k);
  for (int i = 0; i < 15; ++i) {
    out[i] = history_.levels >= 2 ? history_.y1[j](i) : 0.0;
    out[15 + i] = history_.levels >= 3 ? history_.y2[j](i) : 0.0;
  }
  for (int i = 0; i < 3; ++i) {
    out[30 + i] = history_.displacement[j](i);
    out[33 + i] = history_.rotation[j](i);
  }
}

// Scalars: levels, h1, h2, next_dt, accepted, rejected, failed, smallest, largest,
// after-rejection flag, peak (one per group).
std::vector<double> RodErrorEstimate::pack_scalars(const time::ControllerState& c) const {
  const StepControlTotals& t = c.totals;
  std::vector<double> x = {double(history_.levels), history_.h1,          history_.h2,    c.next_dt,
                           double(t.accepted),      double(t.rejected),   double(t.failed), t.smallest_dt,
                           t.largest_dt,            c.after_rejection ? 1.0 : 0.0};
  x.insert(x.end(), peak_.begin(), peak_.end());
  return x;
}

time::ControllerState RodErrorEstimate::restore(const std::vector<rod::NodeLevel>& y0,
                                                const std::vector<double>& per_node, const std::vector<double>& x) {
  if (x.size() < 10 + rod::kErrorGroups) throw std::invalid_argument("restart point without the adaptive controller's state");
  const size_t n = y0.size();
  history_ = rod::LevelHistory();
  history_.levels = static_cast<int>(x[0]);
  history_.h1 = x[1];
  history_.h2 = x[2];
  history_.y0 = y0;
  history_.y1.resize(n);
  history_.y2.resize(n);
  history_.displacement.resize(n);
  history_.rotation.resize(n);
  for (size_t j = 0; j < n; ++j) {
    const double* p = &per_node[kPerNode * j];
    for (int i = 0; i < 15; ++i) {
      history_.y1[j](i) = p[i];
      history_.y2[j](i) = p[15 + i];
    }
    history_.displacement[j] = Vec3(p[30], p[31], p[32]);
    history_.rotation[j] = Vec3(p[33], p[34], p[35]);
  }
  time::ControllerState c;
  c.next_dt = x[3];
  c.totals.accepted = static_cast<long>(x[4]);
  c.totals.rejected = static_cast<long>(x[5]);
  c.totals.failed = static_cast<long>(x[6]);
  c.totals.smallest_dt = x[7];
  c.totals.largest_dt = x[8];
  c.after_rejection = x[9] != 0.0;
  for (int g = 0; g < rod::kErrorGroups; ++g) peak_[g] = x[10 + static_cast<size_t>(g)];
  return c;
}

}  // namespace traverse::solver
