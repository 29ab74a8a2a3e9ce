#include "next_update_test.hpp"

#include <NOX_Abstract_Group.H>
#include <NOX_Solver_Generic.H>
#include <NOX_Thyra_Vector.H>
#include <Teuchos_CommHelpers.hpp>

#include <cmath>
#include <ostream>
#include <string>

#include "thyra_tpetra.hpp"

namespace traverse::solver {

namespace {

const NextUpdateTest::Vector& tpetra(const NOX::Abstract::Vector& v) {
  const auto& t = dynamic_cast<const NOX::Thyra::Vector&>(v);
  return *tt::Extract::getConstTpetraVector(t.getThyraRCPVector());
}

}  // namespace

NextUpdateTest::NextUpdateTest(Teuchos::RCP<NOX::StatusTest::NormF> residual,
                               Teuchos::RCP<NOX::StatusTest::NormWRMS> update, Solve solve)
    : residual_(std::move(residual)), update_(std::move(update)), solve_(std::move(solve)) {}

NOX::StatusTest::StatusType NextUpdateTest::checkStatus(const NOX::Solver::Generic& problem,
                                                        NOX::StatusTest::CheckType type) {
  status_ = NOX::StatusTest::Unconverged;
  if (type == NOX::StatusTest::None) return status_ = NOX::StatusTest::Unevaluated;
  // Only after a factorisation, where the residual test holds and the update test does not.
  if (problem.getNumIterations() == 0 || residual_->getStatus() != NOX::StatusTest::Converged ||
      update_->getStatus() == NOX::StatusTest::Converged)
    return status_;
  const NOX::Abstract::Group& g = problem.getSolutionGroup();
  if (!g.isF()) return status_;
  const Vector& f = tpetra(g.getF());
  const Vector& x = tpetra(g.getX());
  if (d_.is_null() || !d_->getMap()->isSameAs(*f.getMap())) d_ = Teuchos::rcp(new Vector(f.getMap()));
  ++solves_;
  if (!solve_(f, *d_)) return status_;
  // NOX's NormWRMS of the update: sqrt(sum (d_i / (rtol |x_i| + atol))^2 / N).
  const double rtol = update_->getRTOL(), atol = update_->getATOL();
  const auto xv = x.getData();
  const auto dv = d_->getData();
  double local = 0.0;
  for (Teuchos::ArrayRCP<const double>::size_type i = 0; i < xv.size(); ++i) {
    const double u = dv[i] / (rtol * std::abs(xv[i]) + atol);
    local += u * u;
  }
  double sum = local;
  Teuchos::reduceAll<int, double>(*x.getMap()->getComm(), Teuchos::REDUCE_SUM, 1, &local, &sum);
  wrms_ = std::sqrt(sum / static_cast<double>(x.getGlobalLength()));
  if (wrms_ < update_->getTolerance()) status_ = NOX::StatusTest::Converged;
  return status_;
}

std::ostream& NextUpdateTest::print(std::ostream& stream, int indent) const {
  stream << std::string(static_cast<size_t>(indent), ' ') << status_
         << "Next Newton update (last factorisation) WRMS = " << wrms_ << " < " << update_->getTolerance() << "\n";
  return stream;
}

}  // namespace traverse::solver
