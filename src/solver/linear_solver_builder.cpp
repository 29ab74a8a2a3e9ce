#include "linear_solver_builder.hpp"

#include <Amesos2.hpp>
#include <Stratimikos_DefaultLinearSolverBuilder.hpp>
#include <Teuchos_AbstractFactoryStd.hpp>
#include <Thyra_Amesos2LinearOpWithSolveFactory_decl.hpp>
#include <Thyra_Amesos2LinearOpWithSolve_decl.hpp>
#include <Thyra_TpetraThyraWrappers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <algorithm>
#include <functional>
#include <string>
#include <vector>

#include "block_tridiagonal_preconditioner.hpp"
#include "reusable_ifpack2_factory.hpp"
#include "traverse/solver/block_tridiagonal_operator.hpp"
#include "traverse/solver/rod_step_model.hpp"

namespace traverse::solver {

namespace {

using Matrix = Tpetra::CrsMatrix<double>;
using MV = Tpetra::MultiVector<double>;
using Converter = Thyra::TpetraOperatorVectorExtraction<double, Matrix::local_ordinal_type,
                                                        Matrix::global_ordinal_type, Matrix::node_type>;

/// Amesos2 KLU2 as a Thyra LOWS factory that keeps its Amesos2 solver object: the symbolic
/// factorisation (ordering) is done once for the matrix object, and every later
/// initializeOp on the same matrix only refactors numerically - and not even that when the
/// matrix values did not change (its version, from the model, is the one last factored).
/// Stratimikos' adapter calls setA with a clean phase instead, redoing the symbolic phase.
class ReusingKlu2Factory : public Thyra::Amesos2LinearOpWithSolveFactory<double> {
 public:
  ReusingKlu2Factory(std::function<long()> version, std::shared_ptr<DirectSolverStats> stats)
      : Thyra::Amesos2LinearOpWithSolveFactory<double>(Thyra::Amesos2::KLU2),
        version_(std::move(version)),
        stats_(std::move(stats)) {}

  void initializeOp(const Teuchos::RCP<const Thyra::LinearOpSourceBase<double>>& src,
                    Thyra::LinearOpWithSolveBase<double>* op, const Thyra::ESupportSolveUse) const override {
    TEUCHOS_TEST_FOR_EXCEPT(op == nullptr || src.is_null() || src->getOp().is_null());
    const auto t0 = std::chrono::steady_clock::now();
    const Teuchos::RCP<const Thyra::LinearOpBase<double>> fwd = src->getOp();
    const auto A = Teuchos::rcp_dynamic_cast<const Matrix>(Converter::getConstTpetraOperator(fwd), true);
    auto& lows = Teuchos::dyn_cast<Thyra::Amesos2LinearOpWithSolve<double>>(*op);
    const long v = version_ ? version_() : -1;
    if (solver_.is_null() || matrix_ != A.get()) {
      solver_ = ::Amesos2::create<Matrix, MV>("klu2", A);
      solver_->symbolicFactorization();
      solver_->numericFactorization();
      matrix_ = A.get();
      ++stats_->symbolic;
      ++stats_->numeric;
    } else if (v < 0 || v != factored_version_) {
      solver_->setA(A, ::Amesos2::SYMBFACT);  // same matrix object, same graph: keep the ordering
      solver_->numericFactorization();
      ++stats_->numeric;
    } else {
      ++stats_->reused;  // values unchanged since the last factorisation (modified Newton)
    }
    factored_version_ = v;
    lows.initialize(fwd, src, solver_);
    stats_->seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }

  void uninitializeOp(Thyra::LinearOpWithSolveBase<double>* op,
                      Teuchos::RCP<const Thyra::LinearOpSourceBase<double>>* src,
                      Teuchos::RCP<const Thyra::PreconditionerBase<double>>* prec,
                      Teuchos::RCP<const Thyra::LinearOpSourceBase<double>>* approx,
                      Thyra::ESupportSolveUse*) const override {
    // Hand back the operator source; the Amesos2 solver stays here for the next initializeOp.
    auto& lows = Teuchos::dyn_cast<Thyra::Amesos2LinearOpWithSolve<double>>(*op);
    if (src) *src = lows.get_fwdOpSrc();
    if (prec) *prec = Teuchos::null;
    if (approx) *approx = Teuchos::null;
  }

  std::string description() const override { return "traverse::solver::ReusingKlu2Factory"; }

 private:
  std::function<long()> version_;
  std::shared_ptr<DirectSolverStats> stats_;
  mutable Teuchos::RCP<::Amesos2::Solver<Matrix, MV>> solver_;
  mutable const Matrix* matrix_ = nullptr;
  mutable long factored_version_ = -2;
};

/// The block-tridiagonal LU as a LinearOpWithSolve (BlockTridiagonalSolveFactory).
class BlockTridiagonalLows : public Thyra::LinearOpWithSolveBase<double> {
 public:
  void initialize(const Teuchos::RCP<const Thyra::LinearOpBase<double>>& fwd,
                  const Teuchos::RCP<const Thyra::LinearOpSourceBase<double>>& src,
                  const Teuchos::RCP<const BlockTridiagonalPreconditioner>& lu, double tolerance) {
    fwd_ = fwd;
    src_ = src;
    lu_ = lu;
    tolerance_ = tolerance;
  }
  const Teuchos::RCP<const Thyra::LinearOpSourceBase<double>>& source() const { return src_; }
  void uninitialize() {
    fwd_ = Teuchos::null;
    src_ = Teuchos::null;
  }

  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> range() const override {
    return fwd_.is_null() ? Teuchos::null : fwd_->range();
  }
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> domain() const override {
    return fwd_.is_null() ? Teuchos::null : fwd_->domain();
  }

 protected:
  bool opSupportedImpl(Thyra::EOpTransp t) const override { return t == Thyra::NOTRANS; }
  void applyImpl(const Thyra::EOpTransp t, const Thyra::MultiVectorBase<double>& X,
                 const Teuchos::Ptr<Thyra::MultiVectorBase<double>>& Y, const double alpha,
                 const double beta) const override {
    Thyra::apply(*fwd_, t, X, Y, alpha, beta);
  }
  bool solveSupportsImpl(Thyra::EOpTransp t) const override { return t == Thyra::NOTRANS; }
  bool solveSupportsSolveMeasureTypeImpl(Thyra::EOpTransp t, const Thyra::SolveMeasureType&) const override {
    return t == Thyra::NOTRANS;
  }
  Thyra::SolveStatus<double> solveImpl(const Thyra::EOpTransp t, const Thyra::MultiVectorBase<double>& B,
                                       const Teuchos::Ptr<Thyra::MultiVectorBase<double>>& X,
                                       const Teuchos::Ptr<const Thyra::SolveCriteria<double>>) const override {
    TEUCHOS_TEST_FOR_EXCEPTION(t != Thyra::NOTRANS, std::invalid_argument,
                               "block-tridiagonal LU: only NOTRANS solves are supported");
    const auto b = Converter::getConstTpetraMultiVector(Teuchos::rcpFromRef(B));
    const auto x = Converter::getTpetraMultiVector(Teuchos::rcpFromPtr(X));
    lu_->apply(*b, *x);
    // Residual check and iterative refinement (x += LU^{-1} (b - A x)); the two work vectors
    // are kept between solves (Newton solves once per iteration with the same map).
    const size_t nv = b->getNumVectors();
    if (r_.is_null() || r_->getNumVectors() != nv || !r_->getMap()->isSameAs(*b->getMap())) {
      r_ = Teuchos::rcp(new MV(b->getMap(), nv));
      dx_ = Teuchos::rcp(new MV(b->getMap(), nv));
    }
    MV& r = *r_;
    MV& dx = *dx_;
    std::vector<double> nb(nv), nr(nv);
    b->normInf(Teuchos::ArrayView<double>(nb));
    double worst = 0.0;
    for (int pass = 0; pass <= 2; ++pass) {
      lu_->apply_matrix(*x, r);
      r.update(1.0, *b, -1.0);
      r.normInf(Teuchos::ArrayView<double>(nr));
      worst = 0.0;
      for (size_t j = 0; j < nv; ++j) {
        const double q = nb[j] > 0.0 ? nr[j] / nb[j] : nr[j];
        // Tpetra's normInf of a vector holding NaN can return -inf: not finite = failed.
        worst = std::isfinite(q) && q >= 0.0 ? std::max(worst, q) : std::numeric_limits<double>::infinity();
        if (std::isinf(worst)) break;
      }
      if (worst <= tolerance_ || pass == 2 || std::isinf(worst)) break;
      lu_->apply(r, dx);
      x->update(1.0, dx, 1.0);
    }
    Thyra::SolveStatus<double> st;
    st.solveStatus = worst <= tolerance_ ? Thyra::SOLVE_STATUS_CONVERGED : Thyra::SOLVE_STATUS_UNCONVERGED;
    st.achievedTol = worst;
    if (st.solveStatus != Thyra::SOLVE_STATUS_CONVERGED)  // a message only where there is news
      st.message = "block-tridiagonal LU, max|b - A x| / max|b| = " + std::to_string(worst);
    return st;
  }

 private:
  Teuchos::RCP<const Thyra::LinearOpBase<double>> fwd_;
  Teuchos::RCP<const Thyra::LinearOpSourceBase<double>> src_;
  Teuchos::RCP<const BlockTridiagonalPreconditioner> lu_;
  double tolerance_ = 1e-12;
  mutable Teuchos::RCP<MV> r_, dx_;
};

/// The block-tridiagonal LU (block_tridiagonal_preconditioner.hpp) as a direct Thyra LOWS
/// factory, without a Krylov method around it: factorised once per new Jacobian version, each
/// solve followed by a residual check and at most two steps of iterative refinement until
/// max|b - A x| <= Tolerance max|b| (column-wise); a solve that does not get there reports
/// SOLVE_STATUS_UNCONVERGED (Newton then fails the step). Stratimikos makes it by the name
/// kBlockTridiagonalLu (BlockTridiagonalSolveStrategy).
class BlockTridiagonalSolveFactory : public Thyra::LinearOpWithSolveFactoryBase<double> {
 public:
  /// `version`: the Jacobian's (empty: refactor at every initializeOp).
  void set_jacobian_version(std::function<long()> version) { version_ = std::move(version); }
  void set_stats(std::shared_ptr<DirectSolverStats> stats) { stats_ = std::move(stats); }

  bool isCompatible(const Thyra::LinearOpSourceBase<double>& src) const override {
    if (!Teuchos::rcp_dynamic_cast<const BlockTridiagonalOperator>(src.getOp()).is_null()) return true;
    return !Teuchos::rcp_dynamic_cast<const Matrix>(Converter::getConstTpetraOperator(src.getOp())).is_null();
  }
  Teuchos::RCP<Thyra::LinearOpWithSolveBase<double>> createOp() const override {
    return Teuchos::rcp(new BlockTridiagonalLows);
  }
  void initializeOp(const Teuchos::RCP<const Thyra::LinearOpSourceBase<double>>& src,
                    Thyra::LinearOpWithSolveBase<double>* op, const Thyra::ESupportSolveUse) const override {
    TEUCHOS_TEST_FOR_EXCEPT(op == nullptr || src.is_null() || src->getOp().is_null());
    const auto t0 = std::chrono::steady_clock::now();
    const Teuchos::RCP<const Thyra::LinearOpBase<double>> fwd = src->getOp();
    // W in block storage is factorised as it is; a CrsMatrix is copied into blocks.
    const auto blocks = Teuchos::rcp_dynamic_cast<const BlockTridiagonalOperator>(fwd);
    const auto A = blocks.is_null()
                       ? Teuchos::rcp_dynamic_cast<const Matrix>(Converter::getConstTpetraOperator(fwd), true)
                       : Teuchos::null;
    const void* source = blocks.is_null() ? static_cast<const void*>(A.get()) : static_cast<const void*>(blocks.get());
    const long v = version_ ? version_() : -1;
    if (lu_.is_null() || lu_->source() != source) {
      lu_ = blocks.is_null() ? Teuchos::rcp(new BlockTridiagonalPreconditioner(A))
                             : BlockTridiagonalPreconditioner::on_blocks(blocks);
      lu_->set_left_end_clamp(clamp_left_end_);
      TEUCHOS_TEST_FOR_EXCEPTION(!lu_->exact(), std::runtime_error,
                                 "block-tridiagonal LU as a direct solver: the couplings between ranks "
                                 "cannot be kept ("
                                     << lu_->why_not_exact()
                                     << "); use 'Linear Solver: GMRES' with 'Preconditioner: BLOCK_TRIDIAGONAL'");
      lu_->compute();
      ++stats_->symbolic;
      ++stats_->numeric;
    } else if (v < 0 || v != factored_version_) {
      lu_->compute();
      ++stats_->numeric;
    } else {
      ++stats_->reused;  // values unchanged since the last factorisation (modified Newton)
    }
    factored_version_ = v;
    Teuchos::dyn_cast<BlockTridiagonalLows>(*op).initialize(fwd, src, lu_, tolerance_);
    stats_->seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  void uninitializeOp(Thyra::LinearOpWithSolveBase<double>* op,
                      Teuchos::RCP<const Thyra::LinearOpSourceBase<double>>* src,
                      Teuchos::RCP<const Thyra::PreconditionerBase<double>>* prec,
                      Teuchos::RCP<const Thyra::LinearOpSourceBase<double>>* approx,
                      Thyra::ESupportSolveUse*) const override {
    auto& lows = Teuchos::dyn_cast<BlockTridiagonalLows>(*op);
    if (src) *src = lows.source();
    if (prec) *prec = Teuchos::null;
    if (approx) *approx = Teuchos::null;
    lows.uninitialize();
  }
  bool supportsPreconditionerInputType(const Thyra::EPreconditionerInputType) const override { return false; }
  void initializePreconditionedOp(const Teuchos::RCP<const Thyra::LinearOpSourceBase<double>>&,
                                  const Teuchos::RCP<const Thyra::PreconditionerBase<double>>&,
                                  Thyra::LinearOpWithSolveBase<double>*, const Thyra::ESupportSolveUse) const override {
    TEUCHOS_TEST_FOR_EXCEPTION(true, std::logic_error, "block-tridiagonal LU: takes no preconditioner");
  }

  void setParameterList(const Teuchos::RCP<Teuchos::ParameterList>& pl) override {
    pl->validateParametersAndSetDefaults(*getValidParameters());
    tolerance_ = pl->get<double>("Tolerance");
    clamp_left_end_ = pl->get<bool>("Clamp Left End");
    params_ = pl;
  }
  Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const override {
    auto valid = Teuchos::rcp(new Teuchos::ParameterList(kBlockTridiagonalLu));
    valid->set("Tolerance", 1e-12, "relative residual max|b - A x| / max|b| each solve must reach "
                                   "(after at most two steps of iterative refinement)");
    valid->set("Clamp Left End", false, "factorise a static rod with its left end clamped and correct each solve "
                                        "exactly for the end's own rows (an end that is not clamped)");
    return valid;
  }
  Teuchos::RCP<Teuchos::ParameterList> getNonconstParameterList() override { return params_; }
  Teuchos::RCP<Teuchos::ParameterList> unsetParameterList() override {
    auto old = params_;
    params_ = Teuchos::null;
    return old;
  }
  std::string description() const override { return "traverse::solver::BlockTridiagonalSolveFactory"; }

  /// x = LU^{-1} b with the last factorisation, without refinement; false when there is none.
  bool solve_with_last_factors(const MV& b, MV& x) const {
    if (lu_.is_null() || factored_version_ == -2) return false;
    lu_->apply(b, x);
    return true;
  }

 private:
  std::function<long()> version_;
  std::shared_ptr<DirectSolverStats> stats_ = std::make_shared<DirectSolverStats>();
  double tolerance_ = 1e-12;
  bool clamp_left_end_ = false;
  Teuchos::RCP<Teuchos::ParameterList> params_;
  mutable Teuchos::RCP<BlockTridiagonalPreconditioner> lu_;
  mutable long factored_version_ = -2;
};

}  // namespace

namespace {

void register_factories(Stratimikos::DefaultLinearSolverBuilder& builder) {
  builder.setPreconditioningStrategyFactory(
      Teuchos::abstractFactoryStd<Thyra::PreconditionerFactoryBase<double>, ReusableIfpack2Factory>(),
      "Ifpack2");
  builder.setLinearSolveStrategyFactory(
      Teuchos::abstractFactoryStd<Thyra::LinearOpWithSolveFactoryBase<double>, BlockTridiagonalSolveFactory>(),
      kBlockTridiagonalLu);
}

// A Trilinos exception's message without the lines that locate the throw in Trilinos' sources
// ("file.cpp:64:", "Throw number = 1", "Throw test that evaluated to true: ...").
std::string trilinos_message(const std::exception& e) {
  std::istringstream in(e.what());
  std::string line, out;
  while (std::getline(in, line)) {
    const auto first = line.find_first_not_of(" \t");
    if (first == std::string::npos || line.rfind("Throw ", 0) == 0) continue;
    const auto colon = line.find_last_not_of(" \t");
    if (line[colon] == ':' && (line.find(".cpp:") != std::string::npos || line.find(".hpp:") != std::string::npos))
      continue;
    out += (out.empty() ? "" : " ") + line.substr(first);
  }
  return out.empty() ? e.what() : out;
}

// The builder's strategies for `list`; Trilinos' refusal of a name as std::invalid_argument.
Teuchos::RCP<Thyra::LinearOpWithSolveFactoryBase<double>> linear_solve_strategy(
    Stratimikos::DefaultLinearSolverBuilder& builder, const Teuchos::ParameterList& list) {
  try {
    builder.setParameterList(Teuchos::rcp(new Teuchos::ParameterList(list)));
    (void)builder.createPreconditioningStrategy("");
    return builder.createLinearSolveStrategy("");
  } catch (const std::invalid_argument&) {
    throw;
  } catch (const std::exception& e) {
    throw std::invalid_argument(trilinos_message(e));
  }
}

}  // namespace

void check_stratimikos_list(const Teuchos::ParameterList& list) {
  Stratimikos::DefaultLinearSolverBuilder builder;
  register_factories(builder);
  (void)linear_solve_strategy(builder, list);
}

LinearSolverObjects build_linear_solver(const LinearSolverChoice& choice, std::function<long()> jacobian_version,
                                        std::shared_ptr<DirectSolverStats> stats) {
  Stratimikos::DefaultLinearSolverBuilder builder;
  register_factories(builder);
  Teuchos::RCP<Thyra::LinearOpWithSolveFactoryBase<double>> lows = linear_solve_strategy(builder, choice.stratimikos);
  LinearSolverObjects out;
  if (lows->acceptsPreconditionerFactory()) {
    out.prec = lows->getPreconditionerFactory();
    if (!out.prec.is_null()) lows->unsetPreconditionerFactory(nullptr, nullptr);
  }
  if (auto* block = dynamic_cast<BlockTridiagonalSolveFactory*>(lows.get())) {
    block->set_jacobian_version(std::move(jacobian_version));
    if (stats) block->set_stats(std::move(stats));
  }
  out.lows = lows;
  return out;
}

bool solve_with_last_factors(const Thyra::LinearOpWithSolveFactoryBase<double>& factory, const MV& b, MV& x) {
  const auto* block = dynamic_cast<const BlockTridiagonalSolveFactory*>(&factory);
  return block != nullptr && block->solve_with_last_factors(b, x);
}

bool is_block_tridiagonal_solve_factory(const Thyra::LinearOpWithSolveFactoryBase<double>& factory) {
  return dynamic_cast<const BlockTridiagonalSolveFactory*>(&factory) != nullptr;
}

Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> make_reusing_klu2_factory(
    std::function<long()> jacobian_version, std::shared_ptr<DirectSolverStats> stats) {
  if (!stats) stats = std::make_shared<DirectSolverStats>();
  return Teuchos::rcp(new ReusingKlu2Factory(std::move(jacobian_version), std::move(stats)));
}

}  // namespace traverse::solver
