#include "reusable_ifpack2_factory.hpp"

#include "block_tridiagonal_preconditioner.hpp"

#include <Ifpack2_Factory.hpp>
#include <Thyra_DefaultPreconditioner.hpp>
#include <Thyra_TpetraLinearOp.hpp>
#include <Thyra_TpetraThyraWrappers.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_RowMatrix.hpp>
#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace traverse::solver {

namespace {
using Matrix = Tpetra::CrsMatrix<double>;
using LO = Matrix::local_ordinal_type;
using GO = Matrix::global_ordinal_type;
using Node = Matrix::node_type;
using RowMatrix = Tpetra::RowMatrix<double, LO, GO, Node>;
using Prec = Ifpack2::Preconditioner<double, LO, GO, Node>;
using ThyraTpetraOp = Thyra::TpetraLinearOp<double, LO, GO, Node>;
using TpetraOp = Tpetra::Operator<double, LO, GO, Node>;

Teuchos::RCP<const Matrix> matrix_of(const Thyra::LinearOpSourceBase<double>& src) {
  auto op = Teuchos::rcp_dynamic_cast<const ThyraTpetraOp>(src.getOp());
  if (op.is_null()) return Teuchos::null;
  return Teuchos::rcp_dynamic_cast<const Matrix>(op->getConstTpetraOperator());
}

/// The Tpetra operator this preconditioner already holds (null when it holds none).
Teuchos::RCP<TpetraOp> held_operator(const Thyra::DefaultPreconditioner<double>& dp) {
  const auto held = Teuchos::rcp_dynamic_cast<const ThyraTpetraOp>(dp.getUnspecifiedPrecOp());
  if (held.is_null()) return Teuchos::null;
  return Teuchos::rcp_const_cast<TpetraOp>(held->getConstTpetraOperator());
}

std::string upper(std::string s) {
  std::transform(s.begin(), s.end(), s.begin(), [](unsigned char c) { return std::toupper(c); });
  return s;
}
}  // namespace

ReusableIfpack2Factory::ReusableIfpack2Factory() {
  params_ = Teuchos::rcp(new Teuchos::ParameterList(*getValidParameters()));
}

bool ReusableIfpack2Factory::isCompatible(const Thyra::LinearOpSourceBase<double>& src) const {
  return !matrix_of(src).is_null();
}

Teuchos::RCP<Thyra::PreconditionerBase<double>> ReusableIfpack2Factory::createPrec() const {
  return Teuchos::rcp(new Thyra::DefaultPreconditioner<double>);
}

void ReusableIfpack2Factory::initializePrec(
    const Teuchos::RCP<const Thyra::LinearOpSourceBase<double>>& src,
    Thyra::PreconditionerBase<double>* prec, const Thyra::ESupportSolveUse) const {
  const auto A = matrix_of(*src);
  if (A.is_null()) throw std::invalid_argument("ReusableIfpack2Factory: the operator is not a Tpetra::CrsMatrix");
  auto* dp = dynamic_cast<Thyra::DefaultPreconditioner<double>*>(prec);
  if (!dp) throw std::invalid_argument("ReusableIfpack2Factory: prec must come from createPrec()");

  const std::string type = upper(params_->get<std::string>("Prec Type"));
  const int overlap = params_->get<int>("Overlap");
  Teuchos::ParameterList settings = params_->sublist("Ifpack2 Settings");
  if (type == "SCHWARZ" && !settings.isParameter("schwarz: overlap level"))
    settings.set("schwarz: overlap level", overlap);

  if (type == "BLOCK_TRIDIAGONAL") {  // traverse's own exact block-tridiagonal LU
    auto bt = Teuchos::rcp_dynamic_cast<BlockTridiagonalPreconditioner>(held_operator(*dp));
    if (!bt.is_null() && bt->source() != A.get()) bt = Teuchos::null;
    if (bt.is_null()) {
      bt = Teuchos::rcp(new BlockTridiagonalPreconditioner(A));
      ++counters_.created;
      ++counters_.initialized;
      dp->initializeUnspecified(Thyra::createLinearOp(Teuchos::RCP<TpetraOp>(bt)));
    }
    bt->compute();
    ++counters_.computed;
    return;
  }
  // The Ifpack2 object already held by this preconditioner, if it was built for A.
  Teuchos::RCP<Prec> ip = Teuchos::rcp_dynamic_cast<Prec>(held_operator(*dp));
  if (!ip.is_null() && ip->getMatrix().get() != static_cast<const RowMatrix*>(A.get())) ip = Teuchos::null;
  if (ip.is_null()) {
    ip = Ifpack2::Factory::create<RowMatrix>(type, Teuchos::RCP<const RowMatrix>(A));
    if (ip.is_null()) throw std::invalid_argument("ReusableIfpack2Factory: unknown Ifpack2 'Prec Type' " + type);
    ip->setParameters(settings);
    ip->initialize();
    ++counters_.created;
    ++counters_.initialized;
    dp->initializeUnspecified(Thyra::createLinearOp(Teuchos::RCP<TpetraOp>(ip)));
  } else if (type == "BLOCK_RELAXATION") {
    // Ifpack2 13.2's Banded (and other) containers zero their block storage in initialize()
    // only, so compute() on new values would add to stale factors: initialize again.
    ip->initialize();
    ++counters_.initialized;
  } else if (type == "SCHWARZ" && overlap > 0 && A->getComm()->getSize() > 1) {
    ip->initialize();  // refresh the copied overlap rows
    ++counters_.initialized;
  }
  ip->compute();
  ++counters_.computed;
}

void ReusableIfpack2Factory::uninitializePrec(Thyra::PreconditionerBase<double>* prec,
                                              Teuchos::RCP<const Thyra::LinearOpSourceBase<double>>* src,
                                              Thyra::ESupportSolveUse* use) const {
  // The preconditioner keeps its Ifpack2 object for reuse; nothing to hand back.
  (void)prec;
  if (src) *src = Teuchos::null;
  if (use) *use = Thyra::SUPPORT_SOLVE_UNSPECIFIED;
}

void ReusableIfpack2Factory::setParameterList(const Teuchos::RCP<Teuchos::ParameterList>& pl) {
  if (pl.is_null()) throw std::invalid_argument("ReusableIfpack2Factory: null parameter list");
  pl->validateParametersAndSetDefaults(*getValidParameters());
  params_ = pl;
}

Teuchos::RCP<Teuchos::ParameterList> ReusableIfpack2Factory::getNonconstParameterList() { return params_; }

Teuchos::RCP<Teuchos::ParameterList> ReusableIfpack2Factory::unsetParameterList() {
  auto old = params_;
  params_ = Teuchos::rcp(new Teuchos::ParameterList(*getValidParameters()));
  return old;
}

Teuchos::RCP<const Teuchos::ParameterList> ReusableIfpack2Factory::getParameterList() const { return params_; }

Teuchos::RCP<const Teuchos::ParameterList> ReusableIfpack2Factory::getValidParameters() const {
  static Teuchos::RCP<const Teuchos::ParameterList> valid = [] {
    auto pl = Teuchos::rcp(new Teuchos::ParameterList("Ifpack2"));
    pl->set("Prec Type", "ILUT", "Ifpack2 preconditioner type (ILUT, RILUK, SCHWARZ, RELAXATION, ...) or BLOCK_TRIDIAGONAL (traverse's own)");
    pl->set("Overlap", 0, "Additive Schwarz overlap (used when 'schwarz: overlap level' is absent)");
    pl->sublist("Ifpack2 Settings", false, "Handed to Ifpack2, which validates it")
        .disableRecursiveValidation();
    pl->sublist("VerboseObject", false, "Verbosity (ignored)").disableRecursiveValidation();
    return Teuchos::RCP<const Teuchos::ParameterList>(pl);
  }();
  return valid;
}

std::string ReusableIfpack2Factory::description() const {
  return "traverse::solver::ReusableIfpack2Factory{" + params_->get<std::string>("Prec Type") + "}";
}

}  // namespace traverse::solver
