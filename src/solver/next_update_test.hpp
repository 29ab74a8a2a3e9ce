#pragma once
// A NOX status test that ends a Newton solve one factorisation early: when the residual test
// holds but the last update is not yet below NOX's WRMS update test (quadratic convergence
// makes the last update much larger than the next one), the next Newton update is estimated
// with the last factorisation, d = J(x_{k-1})^{-1} f(x_k), at the cost of one solve; if d
// passes the same WRMS test (weights rtol |x_k| + atol), the solve has converged and d is kept
// for the Newton solver to apply (x <- x_k - d). NOX's own test would instead take one more
// iteration (an assembly, a factorisation and a solve) only to see an update of round-off
// size. Private to the solver module.
#include <NOX_StatusTest_Generic.H>
#include <NOX_StatusTest_NormF.H>
#include <NOX_StatusTest_NormWRMS.H>
#include <Tpetra_Vector.hpp>

#include <functional>

namespace traverse::solver {

class NextUpdateTest : public NOX::StatusTest::Generic {
 public:
  using Vector = Tpetra::Vector<double>;
  /// d = (last factorisation)^{-1} f; false when there is no factorisation to use.
  using Solve = std::function<bool(const Vector& f, Vector& d)>;

  /// `residual` and `update`: the solve's own tests, checked before this one in the same
  /// combination (this test only acts where the first has converged and the second has not).
  NextUpdateTest(Teuchos::RCP<NOX::StatusTest::NormF> residual, Teuchos::RCP<NOX::StatusTest::NormWRMS> update,
                 Solve solve);

  NOX::StatusTest::StatusType checkStatus(const NOX::Solver::Generic& problem,
                                          NOX::StatusTest::CheckType type) override;
  NOX::StatusTest::StatusType getStatus() const override { return status_; }
  std::ostream& print(std::ostream& stream, int indent = 0) const override;

  /// Whether the last check converged on the estimated update, which is then update().
  bool taken() const { return status_ == NOX::StatusTest::Converged; }
  const Vector& update() const { return *d_; }
  /// WRMS of the estimated update at the last check that computed one.
  double wrms() const { return wrms_; }
  /// Solves made by the test.
  int solves() const { return solves_; }

 private:
  Teuchos::RCP<NOX::StatusTest::NormF> residual_;
  Teuchos::RCP<NOX::StatusTest::NormWRMS> update_;
  Solve solve_;
  Teuchos::RCP<Vector> d_;
  NOX::StatusTest::StatusType status_ = NOX::StatusTest::Unevaluated;
  double wrms_ = 0.0;
  int solves_ = 0;
};

}  // namespace traverse::solver
