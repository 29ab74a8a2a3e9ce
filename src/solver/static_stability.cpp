// Small-vibration eigenvalues of a static state: K_s phi = omega^2 M_s phi by Anasazi
// Block Krylov-Schur on T = (K_s - sigma M_s)^-1 M_s (largest |theta| = omega^2 nearest sigma,
// omega^2 = sigma + 1/theta). M_s is singular (constraint rows): its infinite eigenvalues map
// to theta = 0 and stay out of the way; the start vector is T applied to a fixed vector.
//
// The pencil is not symmetric (the first-order form's rows are balance laws, compatibility and
// constraints, its unknowns r, rotation, kappa and n: |K_s - K_s^T| is of the size of |K_s|),
// so the non-Hermitian solver is the right one; its eigenvalues are real for a conservative
// state but ill-conditioned (eigenvalue condition numbers 1e10 to 1e12 on a straight rod of
// 80 cells), so T must be applied exactly: a Krylov solve to a relative residual of 1e-12 (the statics'
// GMRES + ILUT on several ranks) is a slightly different, not even linear, operator, and
// splits a double eigenvalue into two, or into a complex pair. T is therefore applied with a
// direct solver: the statics solver when it is one (KLU2 on one rank), else the
// block-tridiagonal LU, exact across ranks and residual-checked; only when that fails (its
// pivots eliminate from the left end) does the statics solver's Krylov solve apply T.
#include <AnasaziBasicEigenproblem.hpp>
#include <AnasaziBlockKrylovSchurSolMgr.hpp>
#include <AnasaziTpetraAdapter.hpp>
#include <Tpetra_Operator.hpp>
#include <algorithm>
#include <cmath>
#include <functional>
#include <optional>

#include "static_context.hpp"

namespace traverse::solver {

namespace {

using Vector = StaticRodModel::Vector;
using Matrix = StaticRodModel::Matrix;
using MV = Tpetra::MultiVector<double>;
using OP = Tpetra::Operator<double>;

class ShiftInvert : public OP {
 public:
  // A is factorised (or its preconditioner set up) once, here; every apply only solves.
  ShiftInvert(const StaticContext& ctx, const StaticLinearSolver& linear, Teuchos::RCP<Matrix> A,
              Teuchos::RCP<Matrix> M)
      : linear_(linear), A_(std::move(A)), M_(std::move(M)) {
    failed_ = !linear_.set_up(ctx.model->get_x_space(), *A_);
  }
  Teuchos::RCP<const Tpetra::Map<>> getDomainMap() const override { return M_->getDomainMap(); }
  Teuchos::RCP<const Tpetra::Map<>> getRangeMap() const override { return M_->getRangeMap(); }
  void apply(const MV& X, MV& Y, Teuchos::ETransp mode = Teuchos::NO_TRANS, double alpha = 1.0,
             double beta = 0.0) const override {
    if (mode != Teuchos::NO_TRANS) throw std::logic_error("ShiftInvert: transpose not available");
    Vector b(M_->getRangeMap()), y(M_->getRangeMap());
    for (size_t k = 0; k < X.getNumVectors(); ++k) {
      M_->apply(*X.getVector(k), b);
      y.putScalar(0.0);
      if (failed_ || !linear_.solve(b, y)) {
        failed_ = true;
        y.putScalar(0.0);
      }
      Y.getVectorNonConst(k)->update(alpha, y, beta);
    }
  }
  bool failed() const { return failed_; }

 private:
  const StaticLinearSolver& linear_;
  Teuchos::RCP<Matrix> A_, M_;
  mutable bool failed_ = false;
};

}  // namespace

double stability_shift(const rod::StaticProblem& problem, const StabilityOptions& options) {
  if (std::isfinite(options.shift)) return options.shift;
  const auto& b = problem.base;
  return -0.01 * b.props.bending_rate(b.length);
}

namespace {

// K - sigma M on the graph of K (both filled at x with parameters p).
Teuchos::RCP<Matrix> shifted_stiffness(const StaticRodModel& model, const Vector& x, const Params& p, double sigma,
                                       const Matrix& M) {
  auto A = model.new_matrix();
  model.fill_jacobian(x, p, *A);
  A->resumeFill();
  const size_t nrows = A->getNodeNumRows();
  for (size_t r = 0; r < nrows; ++r) {
    typename Matrix::local_inds_host_view_type idx;
    typename Matrix::values_host_view_type val;
    M.getLocalRowView(static_cast<mesh::LO>(r), idx, val);
    std::vector<mesh::LO> ii(idx.extent(0));
    std::vector<double> vv(idx.extent(0));
    for (size_t k = 0; k < ii.size(); ++k) {
      ii[k] = idx(k);
      vv[k] = -sigma * val(k);
    }
    A->sumIntoLocalValues(static_cast<mesh::LO>(r), static_cast<mesh::LO>(ii.size()), vv.data(), ii.data());
  }
  A->fillComplete();
  return A;
}

// A deterministic start vector (independent of the rank count).
Teuchos::RCP<MV> start_vector(const Teuchos::RCP<const Tpetra::Map<>>& map) {
  auto v0 = Teuchos::rcp(new MV(map, 1));
  auto d = v0->getDataNonConst(0);
  for (Teuchos_Ordinal i = 0; i < d.size(); ++i) {
    const double g = static_cast<double>(map->getGlobalElement(static_cast<mesh::LO>(i)));
    d[i] = std::sin(0.37 * g + 0.1) + 0.5 * std::cos(1.91 * g);
  }
  return v0;
}

Anasazi::ReturnType solve_eigenproblem(const Teuchos::RCP<Anasazi::BasicEigenproblem<double, MV, OP>>& problem,
                                       int nev, double tolerance) {
  Teuchos::ParameterList pl;
  pl.set("Which", std::string("LM"));
  pl.set("Block Size", 1);
  pl.set("Num Blocks", std::max(3 * nev + 10, 30));
  pl.set("Maximum Restarts", 200);
  pl.set("Convergence Tolerance", tolerance);
  pl.set("Verbosity", static_cast<int>(Anasazi::Errors));
  Anasazi::BlockKrylovSchurSolMgr<double, MV, OP> mgr(problem, pl);
  try {
    return mgr.solve();
  } catch (const std::exception&) {
    return Anasazi::Unconverged;
  }
}

// omega^2 = sigma + 1/theta in ascending real part, with the unstable count and the column of
// the eigenvector nearest zero (-1 without one).
int sort_eigenvalues(const Anasazi::Eigensolution<double, MV>& sol, double sigma, Stability& out) {
  struct Ev {
    double re, im;
    int col;
  };
  std::vector<Ev> ev;
  for (int i = 0; i < sol.numVecs; ++i) {
    const double tr = sol.Evals[static_cast<size_t>(i)].realpart, ti = sol.Evals[static_cast<size_t>(i)].imagpart;
    const double m2 = tr * tr + ti * ti;
    if (!(m2 > 0.0)) continue;
    ev.push_back({sigma + tr / m2, -ti / m2, i});
  }
  std::sort(ev.begin(), ev.end(), [](const Ev& a, const Ev& b) { return a.re < b.re; });
  double best = std::numeric_limits<double>::infinity();
  int best_col = -1;
  for (const Ev& e : ev) {
    out.eigenvalues.push_back(e.re);
    out.imaginary.push_back(e.im);
    if (e.re < 0.0) ++out.unstable_modes;
    if (std::abs(e.re) < best) {
      best = std::abs(e.re);
      best_col = e.col;
      out.critical = e.re;
    }
  }
  return best_col;
}

}  // namespace

Stability compute_stability(const StaticContext& ctx, const Vector& x, const Params& p,
                            const StabilityOptions& options) {
  const StaticRodModel& model = *ctx.model;
  const double sigma = stability_shift(model.problem(), options);
  auto M = model.new_matrix();
  model.fill_mass(x, *M);
  auto A = shifted_stiffness(model, x, p, sigma, *M);
  const int nev = std::max(1, options.num_eigenvalues);
  // One attempt with one linear solver for K_s - sigma M_s; nullopt when a set-up or a solve
  // failed (every rank alike: the solver's verdicts are global).
  auto attempt = [&](const StaticLinearSolver& linear) -> std::optional<Stability> {
    Stability out;
    out.linear_solver = linear.choice().resolved;
    const long set_ups = linear.set_up_count(), solves = linear.solve_count();
    auto op = Teuchos::rcp(new ShiftInvert(ctx, linear, A, M));
    auto init = Teuchos::rcp(new MV(M->getRowMap(), 1));
    op->apply(*start_vector(M->getRowMap()), *init);
    if (op->failed()) return std::nullopt;
    auto problem = Teuchos::rcp(new Anasazi::BasicEigenproblem<double, MV, OP>(op, init));
    problem->setHermitian(false);
    problem->setNEV(nev);
    if (!problem->setProblem()) return out;
    const Anasazi::ReturnType ret = solve_eigenproblem(problem, nev, options.tolerance);
    if (op->failed()) return std::nullopt;
    const auto& sol = problem->getSolution();
    out.converged = ret == Anasazi::Converged && sol.numVecs >= nev;
    out.factorisations = static_cast<int>(linear.set_up_count() - set_ups);
    out.solves = static_cast<int>(linear.solve_count() - solves);
    const int best_col = sort_eigenvalues(sol, sigma, out);
    if (best_col >= 0) {
      Vector phi(M->getRowMap());
      phi.update(1.0, *sol.Evecs->getVector(best_col), 0.0);
      out.critical_mode = rod::normalised_mode(model.gather(x), model.gather(phi));
    }
    return out;
  };
  const LinearSolverChoice& given = ctx.linear.choice();
  if (!given.direct && !given.block_tridiagonal_direct) {
    const StaticLinearSolver lu(std::function<long()>(), ctx.comm);
    if (std::optional<Stability> s = attempt(lu)) return *s;
  }
  if (std::optional<Stability> s = attempt(ctx.linear)) return *s;
  Stability failed;
  failed.linear_solver = given.resolved;
  return failed;
}

}  // namespace traverse::solver
