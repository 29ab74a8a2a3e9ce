// One NOX Newton solve of the static rod model (static_newton.hpp).
#include "static_newton.hpp"
#include "thyra_tpetra.hpp"

#include <NOX_Observer.hpp>
#include <NOX_Solver_Factory.H>
#include <NOX_Solver_Generic.H>
#include <NOX_SolverStats.hpp>
#include <NOX_StatusTest_Combo.H>
#include <NOX_StatusTest_Divergence.H>
#include <NOX_StatusTest_FiniteValue.H>
#include <NOX_StatusTest_MaxIters.H>
#include <NOX_StatusTest_NormF.H>
#include <NOX_Thyra_Group.H>
#include <NOX_Thyra_Vector.H>
#include <NOX_Utils.H>
#include <Teuchos_CommHelpers.hpp>

#include <cmath>
#include <cstdio>
#include <limits>
#include <ostream>

#include "traverse/core/stop_request.hpp"

namespace traverse::solver {

namespace {

using Vector = StaticRodModel::Vector;
using tt::Extract;

const Vector& tpetra(const NOX::Abstract::Vector& v) {
  return *Extract::getConstTpetraVector(dynamic_cast<const NOX::Thyra::Vector&>(v).getThyraRCPVector());
}

/// The scaled update of the last Newton iteration, max_i of rod::scaled_update of the change
/// x_k - x_{k-1} in unknown i (|change| / scale(kind of i), the force in a direction the rod
/// strains in also measured by its strain), against a tolerance; unconverged before the first
/// iteration. Unknown i is unknown i mod 12 of its node (r, theta, kappa, n): every rank owns
/// whole nodes.
class ScaledUpdateTest : public NOX::StatusTest::Generic {
 public:
  ScaledUpdateTest(double tolerance, const std::array<double, 4>& scales, const Vec3& compliance)
      : tolerance_(tolerance), scales_(scales), compliance_(compliance) {}

  NOX::StatusTest::StatusType checkStatus(const NOX::Solver::Generic& problem,
                                          NOX::StatusTest::CheckType type) override {
    if (type == NOX::StatusTest::None) return status_ = NOX::StatusTest::Unevaluated;
    status_ = NOX::StatusTest::Unconverged;
    value_ = std::numeric_limits<double>::infinity();
    if (problem.getNumIterations() == 0) return status_;
    const auto x = tpetra(problem.getSolutionGroup().getX()).getData();
    const auto x0 = tpetra(problem.getPreviousSolutionGroup().getX()).getData();
    double local = 0.0;
    for (Teuchos::ArrayRCP<const double>::size_type i = 0; i < x.size() && std::isfinite(local); ++i) {
      const double s = rod::scaled_update(static_cast<int>(i % 12), x[i] - x0[i], scales_, compliance_);
      local = std::isfinite(s) ? std::max(local, s) : std::numeric_limits<double>::infinity();
    }
    const auto comm = tpetra(problem.getSolutionGroup().getX()).getMap()->getComm();
    Teuchos::reduceAll<int, double>(*comm, Teuchos::REDUCE_MAX, local, Teuchos::outArg(value_));
    if (value_ <= tolerance_) status_ = NOX::StatusTest::Converged;
    return status_;
  }
  NOX::StatusTest::StatusType getStatus() const override { return status_; }
  std::ostream& print(std::ostream& stream, int indent = 0) const override {
    return stream << std::string(static_cast<size_t>(indent), ' ') << status_ << "Scaled update = " << value_
                  << " <= " << tolerance_ << "\n";
  }
  /// The scaled update at the last check (infinite before the first iteration).
  double value() const { return value_; }

 private:
  double tolerance_;
  std::array<double, 4> scales_;
  Vec3 compliance_;
  double value_ = std::numeric_limits<double>::infinity();
  NOX::StatusTest::StatusType status_ = NOX::StatusTest::Unevaluated;
};

/// Polls the stop request before every Newton iteration (the same points on every rank).
class StopPoll : public NOX::Observer {
 public:
  void runPreIterate(const NOX::Solver::Generic& s) override {
    throw_if_stop_requested("the static solve (Newton iteration " + std::to_string(s.getNumIterations() + 1) + ")");
  }
};

Teuchos::RCP<Teuchos::ParameterList> nox_parameters() {
  auto p = Teuchos::rcp(new Teuchos::ParameterList("NOX"));
  p->set("Nonlinear Solver", std::string("Line Search Based"));
  p->sublist("Line Search").set("Method", std::string("Full Step"));
  p->sublist("Direction").set("Method", std::string("Newton"));
  p->sublist("Direction").sublist("Newton").sublist("Linear Solver").set("Tolerance", 1e-12);
  p->sublist("Printing").set("Output Information", static_cast<int>(NOX::Utils::Error));
  // Every test evaluated at every check: the report states where each one stood.
  p->sublist("Solver Options").set("Status Test Check Type", std::string("Complete"));
  p->sublist("Solver Options").set<Teuchos::RCP<NOX::Observer>>("Observer", Teuchos::rcp(new StopPoll));
  return p;
}

std::string fmt(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.3g", v);
  return buf;
}

}  // namespace

StaticSolveReport nox_static_solve(const Teuchos::RCP<StaticRodModel>& model, Vector& x, const StaticNewtonTests& t,
                                   const Teuchos::RCP<StaticRodModel::Matrix>& W) {
  auto normf = Teuchos::rcp(new NOX::StatusTest::NormF(t.residual, NOX::Abstract::Vector::MaxNorm,
                                                       NOX::StatusTest::NormF::Unscaled));
  auto update = Teuchos::rcp(new ScaledUpdateTest(t.update, t.scales, t.compliance));
  auto finite = Teuchos::rcp(new NOX::StatusTest::FiniteValue);
  auto maxit = Teuchos::rcp(new NOX::StatusTest::MaxIters(t.max_iterations));
  auto tests = Teuchos::rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::OR));
  tests->addStatusTest(finite);
  tests->addStatusTest(Teuchos::rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::AND, normf, update)));
  tests->addStatusTest(maxit);

  Teuchos::RCP<Thyra::LinearOpBase<double>> W_op = model->create_W_op();
  if (!W.is_null()) W_op = Thyra::tpetraLinearOp<double, tt::LO, tt::GO, tt::Node>(model->get_x_space(), model->get_x_space(), W);
  NOX::Thyra::Vector guess(Thyra::createVector(Teuchos::rcp(new Vector(x, Teuchos::Copy)), model->get_x_space()));
  auto group = Teuchos::rcp(new NOX::Thyra::Group(guess, Teuchos::RCP<const Thyra::ModelEvaluator<double>>(model),
                                                  W_op, model->get_W_factory(),
                                                  model->create_W_prec(),
                                                  Teuchos::RCP<Thyra::PreconditionerFactoryBase<double>>()));
  Teuchos::RCP<NOX::StatusTest::Divergence> diverged;
  if (t.divergence > 0.0) {
    group->computeF();  // the solver starts from this F (the group keeps it)
    const double threshold = t.divergence * group->getNormF();
    if (threshold > 0.0 && std::isfinite(threshold)) {
      diverged = Teuchos::rcp(new NOX::StatusTest::Divergence(threshold, 2));
      tests->addStatusTest(diverged);
    }
  }
  auto solver = NOX::Solver::buildSolver(group, tests, nox_parameters());
  StaticSolveReport r;
  NOX::StatusTest::StatusType status = NOX::StatusTest::Unevaluated;
  std::string error;
  try {
    status = solver->solve();
  } catch (const StopRequested&) {
    throw;
  } catch (const std::exception& e) {
    error = e.what();
  }
  const NOX::Abstract::Group& g = solver->getSolutionGroup();
  Tpetra::deep_copy(x, tpetra(g.getX()));
  r.converged = status == NOX::StatusTest::Converged;
  r.iterations = solver->getNumIterations();
  r.residual_norm = g.isF() ? g.getF().norm(NOX::Abstract::Vector::MaxNorm) : normf->getNormF();
  if (r.converged) return r;
  if (!error.empty()) {
    r.message = "Newton (NOX) stopped by an exception in iteration " + std::to_string(r.iterations + 1) + ": " + error;
  } else if (finite->getStatus() == NOX::StatusTest::Failed || !std::isfinite(r.residual_norm)) {
    r.message = "Newton diverged (the residual is not finite) in iteration " + std::to_string(r.iterations);
  } else if (!diverged.is_null() && diverged->getStatus() == NOX::StatusTest::Failed) {
    r.message = "Newton diverged (the residual's norm above " + fmt(t.divergence) + " times the initial one in two "
                "iterations) in iteration " + std::to_string(r.iterations);
  } else {
    const bool residual_held = r.residual_norm <= t.residual;
    r.message = "Newton did not converge in " + std::to_string(r.iterations) + " iterations: max |f| " +
                fmt(r.residual_norm) + (residual_held ? " <= " : " > ") + fmt(t.residual) + ", scaled update " +
                fmt(update->value()) + (update->value() <= t.update ? " <= " : " > ") + fmt(t.update) + (residual_held ? " (rounding)" : "");
  }
  const auto stats = solver->getSolverStatistics();
  if (!stats.is_null() && r.iterations > 0 && !stats->linearSolve.lastLinearSolve_Converged)
    r.message += "; the last linear solve did not reach its tolerance";
  return r;
}

}  // namespace traverse::solver
