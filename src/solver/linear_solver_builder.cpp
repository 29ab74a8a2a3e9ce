#include "linear_solver_builder.hpp"

#include <Amesos2.hpp>
#include <Stratimikos_DefaultLinearSolverBuilder.hpp>
#include <Teuchos_AbstractFactoryStd.hpp>
#include <Thyra_Amesos2LinearOpWithSolveFactory_decl.hpp>
#include <Thyra_Amesos2LinearOpWithSolve_decl.hpp>
#include <Thyra_TpetraThyraWrappers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <chrono>
#include <functional>

#include "reusable_ifpack2_factory.hpp"
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

}  // namespace

LinearSolverObjects build_linear_solver(const LinearSolverChoice& choice) {
  Stratimikos::DefaultLinearSolverBuilder builder;
  builder.setPreconditioningStrategyFactory(
      Teuchos::abstractFactoryStd<Thyra::PreconditionerFactoryBase<double>, ReusableIfpack2Factory>(),
      "Ifpack2");
  builder.setParameterList(Teuchos::rcp(new Teuchos::ParameterList(choice.stratimikos)));
  Teuchos::RCP<Thyra::LinearOpWithSolveFactoryBase<double>> lows = builder.createLinearSolveStrategy("");
  LinearSolverObjects out;
  if (lows->acceptsPreconditionerFactory()) {
    out.prec = lows->getPreconditionerFactory();
    if (!out.prec.is_null()) lows->unsetPreconditionerFactory(nullptr, nullptr);
  }
  out.lows = lows;
  return out;
}

Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> make_reusing_klu2_factory(
    std::function<long()> jacobian_version, std::shared_ptr<DirectSolverStats> stats) {
  if (!stats) stats = std::make_shared<DirectSolverStats>();
  return Teuchos::rcp(new ReusingKlu2Factory(std::move(jacobian_version), std::move(stats)));
}

}  // namespace traverse::solver
