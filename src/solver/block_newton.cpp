#include "block_newton.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace traverse::solver {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// NOX's NormWRMS of an update: sqrt(sum (delta_i / (rtol |base_i| + atol))^2 / N).
template <class Delta>
double update_wrms(const BlockNewtonOptions& o, const std::vector<double>& base, Delta delta) {
  double ss = 0.0;
  for (size_t i = 0; i < base.size(); ++i) {
    const double w = 1.0 / (o.update_relative_tolerance * std::abs(base[i]) + o.update_absolute_tolerance);
    const double u = delta(i) * w;
    ss += u * u;
  }
  return std::sqrt(ss) / std::sqrt(static_cast<double>(base.size()));
}
}  // namespace

BlockNewton::BlockNewton(const rod::StepAssembly& assembly, BlockNewtonOptions options)
    : asm_(assembly), opt_(options) {
  const int nodes = asm_.model().num_cells + 1;
  if (asm_.first_owned_node() != 0 || asm_.num_owned_nodes() != nodes || asm_.num_ghosted_nodes() != nodes)
    throw std::invalid_argument("BlockNewton: the assembly must own every node of the rod (one rank)");
  sys_ = std::make_unique<BlockSystem>(nodes, asm_.unknowns_per_node());
  d_.assign(sys_->f().size(), 0.0);
}

BlockNewton::~BlockNewton() = default;

double BlockNewton::evaluate(const std::vector<double>& x) {
  const auto t0 = std::chrono::steady_clock::now();
  sys_->clear();
  dropped_ = asm_.for_each_block(x.data(), [&](const rod::LocalBlock& blk) { sys_->add(blk); });
  ++n_f_;
  t_asm_ += seconds_since(t0);
  return max_abs(sys_->f());
}

NewtonReport BlockNewton::solve(std::vector<double>& x) {
  if (x.size() != d_.size()) throw std::invalid_argument("BlockNewton::solve: x has the wrong size");
  // As NewtonSolver (NOX): an exception inside the kernels or the LU is a failed solve.
  try {
    return iterate(x);
  } catch (const std::exception& e) {
    NewtonReport rep;
    rep.status = std::string("failed: exception: ") + e.what();
    rep.residual_norm = std::numeric_limits<double>::quiet_NaN();
    return rep;
  }
}

bool BlockNewton::next_update_small(std::vector<double>& x, double nf, double& wrms) {
  // f and J at x were just assembled; the factorisation is still the last iteration's, so
  // the solve refines towards J(x)^{-1} f(x) with it (BlockSystem::solve).
  const double achieved = sys_->solve(d_, nf, std::max(opt_.linear_tolerance, opt_.update_test_linear_tolerance));
  if (!(achieved <= 0.5)) return false;
  const double next = update_wrms(opt_, x, [&](size_t i) { return d_[i]; });
  if (!(next < 1.0)) return false;
  wrms = next;  // the update taken last is now this one
  // Taken: the Newton step from x, within the update tolerances of x, whose residual is already
  // below its tolerance (the step's own residual is not evaluated).
  for (size_t i = 0; i < x.size(); ++i) x[i] -= d_[i];
  return true;
}

NewtonReport BlockNewton::iterate(std::vector<double>& x) {
  NewtonReport rep;
  double nf = evaluate(x);
  rep.residual_history.push_back(nf);
  rep.update_wrms = 1e12;  // NOX's value before the first update
  int it = 0;
  bool linear_ok = true;  // NOX's NormWRMS also asks the linear solve's achieved tolerance <= 0.5
  for (;;) {
    if (!std::isfinite(nf)) {
      rep.status = "failed: non-finite residual";
      break;
    }
    if (it > 0 && nf < opt_.residual_tolerance && linear_ok &&
        (rep.update_wrms < 1.0 || (opt_.next_update_test && next_update_small(x, nf, rep.update_wrms)))) {
      rep.converged = true;
      rep.status = "converged";
      break;
    }
    if (it >= opt_.max_iterations) {
      rep.status = "failed: no convergence in " + std::to_string(opt_.max_iterations) + " Newton iterations";
      break;
    }
    const auto t0 = std::chrono::steady_clock::now();
    sys_->factor();
    ++n_lu_;
    t_lu_ += seconds_since(t0);
    const double achieved = sys_->solve(d_, nf, opt_.linear_tolerance);
    x_old_ = x;
    for (size_t i = 0; i < x.size(); ++i) x[i] = x_old_[i] + (-d_[i]);
    ++it;
    nf = evaluate(x);
    rep.residual_history.push_back(nf);
    rep.update_wrms = update_wrms(opt_, x_old_, [&](size_t i) { return x[i] - x_old_[i]; });
    linear_ok = achieved <= 0.5;
  }
  rep.iterations = it;
  rep.residual_norm = nf;
  return rep;
}

BlockNewtonOptions block_newton_options(const ParamList& newton, const LinearSolverChoice& choice) {
  BlockNewtonOptions o;
  o.residual_tolerance = newton.get<double>("Residual Tolerance");
  o.update_relative_tolerance = newton.get<double>("Update Relative Tolerance");
  o.update_absolute_tolerance = newton.get<double>("Update Absolute Tolerance");
  o.max_iterations = newton.get<int>("Max Newton Iterations");
  o.linear_tolerance = choice.linear_tolerance;
  o.next_update_test = newton.get<std::string>("Update Test") == "auto";
  return o;
}

void add_block_newton_counters(const BlockNewton& b, ReuseCounters& c) {
  c.jacobian_evaluations += b.factorizations();
  c.residual_evaluations += b.residual_evaluations();
  c.assembly_seconds += b.assembly_seconds();
  c.linear_setup_seconds += b.factorization_seconds();
  c.numeric_factorizations += b.factorizations();
}

}  // namespace traverse::solver
