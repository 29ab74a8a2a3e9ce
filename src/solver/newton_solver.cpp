#include "traverse/solver/newton_solver.hpp"

#include "thyra_tpetra.hpp"

#include <NOX_Observer.hpp>
#include <NOX_Solver_Factory.H>
#include <NOX_Solver_Generic.H>
#include <NOX_SolverStats.hpp>
#include <NOX_StatusTest_Combo.H>
#include <NOX_StatusTest_FiniteValue.H>
#include <NOX_StatusTest_MaxIters.H>
#include <NOX_StatusTest_NormF.H>
#include <NOX_StatusTest_NormWRMS.H>
#include <NOX_Thyra_Group.H>
#include <NOX_Thyra_Vector.H>
#include <NOX_Utils.H>
#include <Thyra_TpetraThyraWrappers.hpp>
#include <cmath>
#include <vector>

#include "linear_solver_builder.hpp"
#include "next_update_test.hpp"
#include "traverse/solver/rod_step_model.hpp"

namespace traverse::solver {

namespace {
using namespace tt;  // MEB, LO, GO, Node, Extract

/// Records max |f| at the initial guess and after each Newton iteration. (NOX computes the
/// initial residual inside the first step, after runPreIterate: it is taken from the previous
/// solution group after the first iteration.)
class HistoryObserver : public NOX::Observer {
 public:
  std::vector<double> history;
  void runPreSolve(const NOX::Solver::Generic&) override { history.clear(); }
  void runPreIterate(const NOX::Solver::Generic& s) override {
    if (history.empty()) record(s.getSolutionGroup());
  }
  void runPostIterate(const NOX::Solver::Generic& s) override {
    if (history.empty()) record(s.getPreviousSolutionGroup());
    record(s.getSolutionGroup());
  }

 private:
  void record(const NOX::Abstract::Group& g) {
    if (g.isF()) history.push_back(g.getF().norm(NOX::Abstract::Vector::MaxNorm));
  }
};

template <class T>
T get_or(const Teuchos::ParameterList& pl, const std::string& key, const T& fallback) {
  return pl.isType<T>(key) ? pl.get<T>(key) : fallback;
}

template <class T>
void set_default(Teuchos::ParameterList& pl, const std::string& key, const T& value) {
  if (!pl.isParameter(key)) pl.set(key, value);
}
}  // namespace

struct NewtonSolver::Impl {
  Teuchos::RCP<RodStepModel> model;
  Teuchos::RCP<Teuchos::ParameterList> nox;
  Teuchos::RCP<HistoryObserver> observer;
  Teuchos::RCP<NOX::StatusTest::NormF> normf;
  Teuchos::RCP<NOX::StatusTest::NormWRMS> wrms;
  Teuchos::RCP<NOX::StatusTest::MaxIters> maxit;
  Teuchos::RCP<NOX::StatusTest::FiniteValue> finite;
  Teuchos::RCP<NextUpdateTest> next;  ///< null: NOX's own update test alone
  Teuchos::RCP<NOX::StatusTest::Combo> tests;
  Teuchos::RCP<NOX::Thyra::Group> group;
  Teuchos::RCP<NOX::Solver::Generic> solver;
};

NewtonSolver::NewtonSolver(Teuchos::RCP<RodStepModel> model, const Teuchos::ParameterList& params)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.model = model;
  m.nox = Teuchos::rcp(new Teuchos::ParameterList(params.isSublist("NOX") ? params.sublist("NOX")
                                                                           : Teuchos::ParameterList("NOX")));
  m.nox->setName("NOX");
  Teuchos::ParameterList& nox = *m.nox;
  set_default(nox, "Nonlinear Solver", std::string("Line Search Based"));
  set_default(nox.sublist("Line Search"), "Method", get_or<std::string>(params, "Line Search", "Full Step"));
  set_default(nox.sublist("Direction"), "Method", std::string("Newton"));
  Teuchos::ParameterList& lin = nox.sublist("Direction").sublist("Newton").sublist("Linear Solver");
  set_default(lin, "Tolerance", get_or<double>(params, "Linear Tolerance", 1e-12));
  set_default(nox.sublist("Printing"), "Output Information", static_cast<int>(NOX::Utils::Error));
  // Minimal: a test whose verdict cannot change the combination is not evaluated (the update
  // tests only where the residual test holds).
  set_default(nox.sublist("Solver Options"), "Status Test Check Type", std::string("Minimal"));
  m.observer = Teuchos::rcp(new HistoryObserver);
  nox.sublist("Solver Options").set<Teuchos::RCP<NOX::Observer>>("Observer", m.observer);

  m.normf = Teuchos::rcp(new NOX::StatusTest::NormF(get_or<double>(params, "Residual Tolerance", 1e-8),
                                                    NOX::Abstract::Vector::MaxNorm,
                                                    NOX::StatusTest::NormF::Unscaled));
  m.wrms = Teuchos::rcp(new NOX::StatusTest::NormWRMS(get_or<double>(params, "Update Relative Tolerance", 1e-8),
                                                      get_or<double>(params, "Update Absolute Tolerance", 1e-10)));
  m.maxit = Teuchos::rcp(new NOX::StatusTest::MaxIters(get_or<int>(params, "Max Newton Iterations", 20)));
  m.finite = Teuchos::rcp(new NOX::StatusTest::FiniteValue);
  auto converged = Teuchos::rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::AND, m.normf, m.wrms));
  // 'Update Test: auto' with the block-tridiagonal LU: the update test also passes on the next
  // update estimated with the last factorisation (next_update_test.hpp).
  const auto factory = model->get_W_factory();
  if (get_or<std::string>(params, "Update Test", "auto") == "auto" && !factory.is_null() &&
      is_block_tridiagonal_solve_factory(*factory)) {
    m.next = Teuchos::rcp(new NextUpdateTest(m.normf, m.wrms, [factory](const Tpetra::Vector<double>& f,
                                                                         Tpetra::Vector<double>& d) {
      return solve_with_last_factors(*factory, f, d);
    }));
    auto update = Teuchos::rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::OR, m.wrms, m.next));
    converged = Teuchos::rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::AND, m.normf, update));
  }
  m.tests = Teuchos::rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::OR));
  m.tests->addStatusTest(m.finite);
  m.tests->addStatusTest(converged);
  m.tests->addStatusTest(m.maxit);

  const auto nominal = model->getNominalValues();
  NOX::Thyra::Vector x0(nominal.get_x()->clone_v());
  m.group = Teuchos::rcp(new NOX::Thyra::Group(x0, Teuchos::RCP<const Thyra::ModelEvaluator<double>>(model), model->create_W_op(), model->get_W_factory(),
                                               model->create_W_prec(),
                                               Teuchos::RCP<Thyra::PreconditionerFactoryBase<double>>()));
  m.solver = NOX::Solver::buildSolver(m.group, m.tests, m.nox);
}

NewtonSolver::~NewtonSolver() = default;

const Teuchos::ParameterList& NewtonSolver::nox_parameters() const { return *impl_->nox; }

NewtonReport NewtonSolver::solve(Tpetra::Vector<double>& x) {
  Impl& m = *impl_;
  NewtonReport r;
  NOX::StatusTest::StatusType status = NOX::StatusTest::Unevaluated;
  try {
    auto xt = Thyra::createVector(Teuchos::rcpFromRef(x), m.model->get_x_space());
    m.solver->reset(NOX::Thyra::Vector(xt));
    status = m.solver->solve();
    r.status = status == NOX::StatusTest::Converged ? "converged" : "failed";
  } catch (const std::exception& e) {
    r.status = std::string("failed: exception: ") + e.what();
  }
  const NOX::Abstract::Group& g = m.solver->getSolutionGroup();
  const auto& nx = dynamic_cast<const NOX::Thyra::Vector&>(g.getX());
  Tpetra::deep_copy(x, *Extract::getConstTpetraVector(nx.getThyraRCPVector()));
  r.converged = status == NOX::StatusTest::Converged;
  r.iterations = m.solver->getNumIterations();
  r.residual_norm = g.isF() ? g.getF().norm(NOX::Abstract::Vector::MaxNorm) : m.normf->getNormF();
  r.update_wrms = m.wrms->getNormWRMS();
  if (r.converged && !m.next.is_null() && m.next->taken()) {
    // Converged on the estimated next update: take it (its residual is not evaluated).
    x.update(-1.0, m.next->update(), 1.0);
    r.update_wrms = m.next->wrms();
  }
  const auto stats = m.solver->getSolverStatistics();
  if (!stats.is_null()) r.linear_iterations = stats->linearSolve.lastNonlinearSolve_NumLinearIterations;
  r.residual_history = m.observer->history;
  if (!r.converged && r.status == "failed") {
    if (m.finite->getStatus() == NOX::StatusTest::Failed || !std::isfinite(r.residual_norm))
      r.status = "failed: non-finite residual";
    else if (m.maxit->getStatus() == NOX::StatusTest::Failed)
      r.status = "failed: no convergence in " + std::to_string(m.maxit->getMaxIters()) + " Newton iterations";
    else
      r.status = "failed: NOX status " + std::to_string(static_cast<int>(status));
  }
  return r;
}

}  // namespace traverse::solver
