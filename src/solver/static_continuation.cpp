// Statics and continuation through LOCA (see static_continuation.hpp and docs/statics.md).
#include "thyra_tpetra.hpp"
#include "traverse/solver/static_continuation.hpp"

#include <Teuchos_CommHelpers.hpp>
#include <Teuchos_oblackholestream.hpp>

#include <LOCA.H>
#include <LOCA_Thyra.H>
#include <LOCA_Thyra_SaveDataStrategy.H>
#include <LOCA_MultiContinuation_AbstractStrategy.H>
#include <LOCA_MultiContinuation_ExtendedVector.H>
#include <LOCA_StatusTest_Abstract.H>
#include <NOX_StatusTest_Combo.H>
#include <NOX_StatusTest_FiniteValue.H>
#include <NOX_StatusTest_MaxIters.H>
#include <NOX_StatusTest_NormF.H>
#include <NOX_StatusTest_NormWRMS.H>
#include <NOX_Thyra_Vector.H>
#include <Thyra_LinearOpWithSolveFactoryHelpers.hpp>
#include <Thyra_TpetraThyraWrappers.hpp>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <limits>
#include <stdexcept>

#include "linear_solver_builder.hpp"
#include "static_newton.hpp"
#include "traverse/solver/rod_step_model.hpp"
#include "traverse/solver/solver_parameters.hpp"

namespace traverse::solver {

namespace {
using Vector = StaticRodModel::Vector;
using Matrix = StaticRodModel::Matrix;
using namespace tt;  // MEB, LO, GO, Node, Extract

std::vector<rod::StaticNode> rebased(std::vector<rod::StaticNode> nodes) {
  for (auto& n : nodes) n.rebase();
  return nodes;
}

double max_abs(const Vector& v) { return v.normInf(); }
}  // namespace

std::string to_string(BifurcationType t) {
  switch (t) {
    case BifurcationType::fold:
      return "fold";
    case BifurcationType::pitchfork:
      return "pitchfork";
    default:
      throw std::logic_error("to_string: unknown bifurcation type");
  }
}

double max_position_difference(const std::vector<rod::StaticNode>& a, const std::vector<rod::StaticNode>& b) {
  double d = 0.0;
  for (size_t j = 0; j < std::min(a.size(), b.size()); ++j)
    d = std::max(d, (a[j].x.segment<3>(rod::svar::r) - b[j].x.segment<3>(rod::svar::r)).cwiseAbs().maxCoeff());
  return d;
}

// ---------------------------------------------------------------------------------------------
StaticLinearSolver::StaticLinearSolver(const Teuchos::ParameterList& solver, const Comm& comm) : comm_(comm) {
  // On 2+ ranks the default GMRES + Schwarz/KLU2 fails for statics: a rank's overlapped block
  // is a sub-rod whose cut end acts as a free end, a mechanism when the other end is pinned or
  // free (singular subdomain matrix; the dynamic step has inertia there). The default here is
  // GMRES + ILUT with its diagonal shift; an explicit "Preconditioner" is respected.
  Teuchos::ParameterList given = solver;
  if (comm->getSize() > 1 && !given.isParameter("Preconditioner") && !given.isSublist("Stratimikos"))
    given.set("Preconditioner", std::string("ILUT"));
  choice_ = LinearSolverChoice::resolve(validated_solver_parameters(given), comm->getSize());
  LinearSolverObjects objs = build_linear_solver(choice_);
  if (!objs.prec.is_null()) {
    auto l = Teuchos::rcp_const_cast<Thyra::LinearOpWithSolveFactoryBase<double>>(objs.lows);
    l->setPreconditionerFactory(objs.prec, "Ifpack2");
  }
  lows_ = objs.lows;
}

StaticLinearSolver::StaticLinearSolver(std::function<long()> jacobian_version, const Comm& comm, bool clamp_left_end)
    : comm_(comm) {
  choice_ = LinearSolverChoice::resolve(validated_solver_parameters(Teuchos::ParameterList()), comm->getSize(),
                                        LinearSolverChoice::Use::time_step);
  if (clamp_left_end) {
    choice_.stratimikos.sublist("Linear Solver Types").sublist(kBlockTridiagonalLu).set("Clamp Left End", true);
    choice_.resolved += ", the left end clamped and corrected";
  }
  lows_ = build_linear_solver(choice_, std::move(jacobian_version)).lows;
}

bool StaticLinearSolver::everywhere(bool local) const {
  const int l = local ? 1 : 0;
  int g = 0;
  Teuchos::reduceAll<int, int>(*comm_, Teuchos::REDUCE_MIN, l, Teuchos::outArg(g));
  return g == 1;
}

bool StaticLinearSolver::set_up(const Teuchos::RCP<const Thyra::VectorSpaceBase<double>>& space, const Matrix& W) const {
  const bool debug = std::getenv("TRAVERSE_STATICS_DEBUG") != nullptr;
  ++set_ups_;
  space_ = space;
  auto Wc = Teuchos::rcp_const_cast<Matrix>(Teuchos::rcpFromRef(W));
  auto op = Thyra::tpetraLinearOp<double, LO, GO, Node>(space, space, Wc);
  bool ok = true;
  op_ = Teuchos::null;
  try {
    op_ = Thyra::linearOpWithSolve<double>(*lows_, op);  // factorisation / preconditioner set-up
  } catch (const std::exception& e) {
    if (debug) std::cout << "solve set-up: " << e.what() << "\n";
    ok = false;
  }
  return everywhere(ok);
}

bool StaticLinearSolver::solve(const Vector& b, Vector& y) const {
  if (op_.is_null()) throw std::logic_error("StaticLinearSolver::solve: no successful set_up");
  ++solves_;
  const bool debug = std::getenv("TRAVERSE_STATICS_DEBUG") != nullptr;
  auto bt = Thyra::createConstVector(Teuchos::rcpFromRef(b), space_);
  auto yt = Thyra::createVector(Teuchos::rcpFromRef(y), space_);
  bool ok = true;
  try {
    const Thyra::SolveStatus<double> st = Thyra::solve<double>(*op_, Thyra::NOTRANS, *bt, yt.ptr());
    if (debug) std::cout << "solve: " << st.message << " " << st.achievedTol << "\n";
    // Belos may flag "unconverged" on a loss-of-accuracy check with a tiny achieved tolerance.
    ok = st.solveStatus != Thyra::SOLVE_STATUS_UNCONVERGED ||
         (st.achievedTol != Thyra::SolveStatus<double>::unknownTolerance() && st.achievedTol <= 1e-9);
  } catch (const std::exception& e) {
    if (debug) std::cout << "solve: " << e.what() << "\n";
    ok = false;
  }
  if (!everywhere(ok)) return false;
  return std::isfinite(y.normInf());
}

StaticContext::StaticContext(const rod::StaticProblem& problem, const std::vector<rod::StaticNode>& state,
                             const Comm& c, const Teuchos::ParameterList& solver)
    : comm(c), linear(solver, c) {
  const int N = problem.base.num_cells;
  if (static_cast<int>(state.size()) != N + 1)
    throw std::invalid_argument("statics: the state must have num_cells + 1 nodes");
  mesh = Teuchos::rcp(new mesh::DistributedMesh(mesh::Mesh1D(problem.base.length, N + 1), comm, 12));
  model = Teuchos::rcp(new StaticRodModel(problem, mesh));
  model->set_state(state);
  model->set_W_factory(linear.factory());
}

StaticSolveReport fixed_parameter_solve(const StaticContext& ctx, Vector& x, const Params& p, int max_iterations,
                                        double ftol, double xtol) {
  StaticNewtonTests tests;  // unit scales: max |dx| <= xtol
  tests.residual = ftol;
  tests.update = xtol;
  tests.max_iterations = max_iterations;
  const rod::StaticProblem given = ctx.model->problem();
  rod::StaticProblem at = given;
  at.values = p;
  ctx.model->set_problem(at);
  // A matrix of its own: the model's W may hold the Jacobian of a LOCA group (a landing solve
  // runs inside the stepper).
  const StaticSolveReport r = nox_static_solve(ctx.model, x, tests, ctx.model->new_matrix());
  ctx.model->set_problem(given);
  return r;
}

StaticSolveReport bordered_newton(const StaticContext& ctx, Vector& x, Params& p, int iparam, const Vector& a,
                                  const Vector& x_ref, double c, int max_iterations, double ftol, double xtol) {
  StaticSolveReport rep;
  const StaticRodModel& model = *ctx.model;
  auto W = model.new_matrix();
  Vector f(x.getMap()), y1(x.getMap()), y2(x.getMap()), fp(x.getMap()), tmp(x.getMap());
  const size_t ip = static_cast<size_t>(iparam);
  for (int it = 0; it <= max_iterations; ++it) {
    model.fill_residual(x, p, f);
    tmp.update(1.0, x, -1.0, x_ref, 0.0);
    const double g = a.dot(tmp) - c;
    rep.residual_norm = max_abs(f);
    if (!std::isfinite(rep.residual_norm)) {
      rep.message = "non-finite residual";
      return rep;
    }
    if (it == max_iterations) break;
    model.fill_jacobian(x, p, *W);
    f.scale(-1.0);
    y1.putScalar(0.0);
    if (!ctx.linear.set_up(model.get_x_space(), *W) || !ctx.linear.solve(f, y1)) {
      rep.message = "linear solve failed";
      return rep;
    }
    // dF/dp, analytic (StaticRodModel::fill_dfdp), solved with the same W (its set-up reused).
    model.fill_dfdp(x, p, static_cast<rod::StaticParameter>(iparam), fp);
    y2.putScalar(0.0);
    if (!ctx.linear.solve(fp, y2)) {
      rep.message = "linear solve failed";
      return rep;
    }
    // J dx + Fp dp = -F, a . dx = -g  =>  dx = y1 - dp y2.
    const double den = a.dot(y2);
    if (!(std::abs(den) > 0.0)) {
      rep.message = "singular bordered system";
      return rep;
    }
    const double dp = (a.dot(y1) + g) / den;
    y1.update(-dp, y2, 1.0);
    p[ip] += dp;
    x.update(1.0, y1, 1.0);
    ++rep.iterations;
    if (max_abs(y1) <= xtol && std::abs(dp) <= xtol * (1.0 + std::abs(p[ip]))) {
      model.fill_residual(x, p, f);
      rep.residual_norm = max_abs(f);
      if (rep.residual_norm <= ftol) {
        rep.converged = true;
        return rep;
      }
    }
  }
  rep.message = "Newton did not converge in " + std::to_string(max_iterations) + " iterations (max|f| = " +
                std::to_string(rep.residual_norm) + ")";
  return rep;
}

// ---------------------------------------------------------------------------------------------
namespace {

struct Run;

/// Records every accepted LOCA point (gather, probes, stability, callback, stop flag).
class Recorder : public LOCA::Thyra::SaveDataStrategy {
 public:
  explicit Recorder(Run& r) : run_(r) {}
  void saveSolution(const NOX::Abstract::Vector& x, double p) override;

 private:
  Run& run_;
};

/// Stops the stepper: the user's stop flag, parameter bounds, max steps (a LOCA status test
/// switches off the stepper's own bounds and step limit).
class StopTest : public LOCA::StatusTest::Abstract {
 public:
  explicit StopTest(Run& r) : run_(r) {}
  LOCA::StatusTest::StatusType checkStatus(const LOCA::Abstract::Iterator& stepper,
                                           LOCA::StatusTest::CheckType) override;
  LOCA::StatusTest::StatusType getStatus() const override { return status_; }
  std::ostream& print(std::ostream& s, int = 0) const override { return s << "traverse statics stop test"; }

 private:
  Run& run_;
  LOCA::StatusTest::StatusType status_ = LOCA::StatusTest::Unevaluated;
};

int sign_of(double v) { return v > 0.0 ? 1 : (v < 0.0 ? -1 : 0); }

bool debug_output() { return std::getenv("TRAVERSE_STATICS_DEBUG") != nullptr; }

struct Run {
  Run(const StaticContext& c, const ContinuationOptions& o, const PointCallback& f, ContinuationResult& r)
      : ctx(c), opt(o), cb(f), res(r) {}
  const StaticContext& ctx;
  const ContinuationOptions& opt;
  const PointCallback& cb;
  ContinuationResult& res;
  std::vector<Teuchos::RCP<Vector>> xs;  ///< distributed state of each point (model frames)
  std::vector<Params> ps;
  std::vector<Stability> stab;           ///< per point (converged = false when not computed)
  bool stop_requested = false;
  bool out_of_bounds = false;
  bool landing_failed = false;
  /// Stability of the last point that passed the acceptance test (reused when it is recorded).
  Teuchos::RCP<Vector> pending_x;
  double pending_p = std::numeric_limits<double>::quiet_NaN();
  Stability pending_s;
  double lambda_ref = 0.0;  ///< largest |lowest omega^2| seen

  size_t ip() const { return static_cast<size_t>(opt.parameter); }
  bool verbose() const { return (opt.verbose || debug_output()) && ctx.comm->getRank() == 0; }

  Stability stability_at(const Vector& x, const Params& p) {
    if (pending_x != Teuchos::null && p[ip()] == pending_p) {
      Vector d(x, Teuchos::Copy);
      d.update(-1.0, *pending_x, 1.0);
      if (d.normInf() == 0.0) return pending_s;
    }
    return compute_stability(ctx, x, p, opt.stability);
  }

  /// Records an accepted point. A point beyond a bound of the parameter, or one that creeps
  /// up to it (closer than 1e-3 max_step), is replaced by the solution on the bound (a
  /// fixed-parameter Newton solve from the interpolation between it and the previous point)
  /// when land_on_bounds; the run then stops.
  void record(const Vector& x, const Params& p) {
    if (!xs.empty()) {  // LOCA re-saves the last point when it finishes on its own target step
      Vector d(x, Teuchos::Copy);
      d.update(-1.0, *xs.back(), 1.0);
      if (d.normInf() <= 1e-9 * (1.0 + x.normInf()) && std::abs(p[ip()] - ps.back()[ip()]) <= 1e-13 * (1.0 + std::abs(p[ip()])))
        return;
    }
    const double v = p[ip()];
    if (xs.empty() || !opt.land_on_bounds) {
      add(x, p);
      return;
    }
    const double prev = ps.back()[ip()];
    const double near = std::max(1e-6 * (1.0 + std::abs(v)), 1e-3 * std::abs(opt.max_step));
    double bound = std::numeric_limits<double>::quiet_NaN();
    if (v > opt.max_value || (v > prev && v > opt.max_value - near)) bound = opt.max_value;
    if (v < opt.min_value || (v < prev && v < opt.min_value + near)) bound = opt.min_value;
    if (!std::isfinite(bound) || v == bound) {
      add(x, p);
      return;
    }
    const double w = (bound - prev) / (v - prev);
    Vector xl(x, Teuchos::Copy);
    xl.update(1.0 - w, *xs.back(), w, x, 0.0);
    Params pl = p;
    pl[ip()] = bound;
    const StaticSolveReport r = fixed_parameter_solve(ctx, xl, pl, opt.max_newton_iterations + 10,
                                                      opt.residual_tolerance, opt.update_tolerance);
    if (r.converged) {
      add(xl, pl);
    } else {
      landing_failed = true;
      add(x, p);
    }
    out_of_bounds = true;
  }

  void add(const Vector& x, const Params& p) {
    ContinuationPoint pt;
    pt.step = static_cast<int>(res.points.size());
    pt.parameter = p[ip()];
    const rod::StaticModel m = ctx.model->problem().model(p);
    pt.state = rebased(ctx.model->gather(x));
    for (const auto& pr : opt.probes) pt.probes.push_back(pr.eval(m, pt.state));
    Stability s;
    if (opt.stability.enabled) {
      s = stability_at(x, p);
      if (s.converged) {
        pt.unstable_modes = s.unstable_modes;
        pt.critical_eigenvalue = s.critical;
        if (!s.eigenvalues.empty()) lambda_ref = std::max(lambda_ref, std::abs(s.eigenvalues.front()));
      }
    }
    s.critical_mode.clear();  // not needed per point
    stab.push_back(std::move(s));
    auto xc = Teuchos::rcp(new Vector(x, Teuchos::Copy));
    xs.push_back(xc);
    ps.push_back(p);
    res.points.push_back(pt);
    if (res.points.size() >= 2) {
      const double prev = res.points[res.points.size() - 2].parameter;
      if ((pt.parameter > prev && pt.parameter >= opt.max_value) || (pt.parameter < prev && pt.parameter <= opt.min_value))
        out_of_bounds = true;
    }
    if (cb) cb(res.points.back());
    if (opt.stop && opt.stop(res.points.back())) stop_requested = true;
  }

  /// Floor of the eigenvalue-change test [1/s^2].
  double eigenvalue_floor() const {
    const auto& b = ctx.model->problem().base;
    return std::max(opt.eigenvalue_floor * lambda_ref, 10.0 * b.props.bending_rate(b.length));
  }

  /// The trend test of the acceptance: the lowest non-negative eigenvalue fell towards zero
  /// over the last two recorded points, the new point (pb, stability s) lies beyond the zero
  /// that their secant predicts, and yet that eigenvalue rose again with no change in the
  /// unstable-mode count: the step jumped past a fold or crossing onto another branch (it can
  /// do so with eigenvalues within the eigenvalue-change test). Fills `why` when it did.
  bool passes_predicted_crossing(const Stability& s, double pb, std::string& why) const {
    const size_t n = stab.size();
    if (n < 2 || !stab[n - 2].converged) return false;
    const int k = s.unstable_modes;
    if (stab[n - 2].unstable_modes != k || stab[n - 1].unstable_modes != k) return false;
    const auto& l0 = stab[n - 2].eigenvalues;
    const auto& l1 = stab[n - 1].eigenvalues;
    const size_t i = static_cast<size_t>(k);
    if (i >= l0.size() || i >= l1.size() || i >= s.eigenvalues.size()) return false;
    const double f0 = l0[i], f1 = l1[i], f2 = s.eigenvalues[i];
    const double p0 = ps[n - 2][ip()], p1 = ps[n - 1][ip()];
    const double d01 = p1 - p0, d12 = pb - p1;
    if (!(f0 > f1 && f1 > 0.0 && f2 > f1 && d01 * d12 > 0.0)) return false;
    const double reach = f1 * d01 / (f0 - f1);  // secant: distance from p1 to the predicted zero
    if (std::abs(d12) <= std::abs(reach)) return false;
    why = "eigenvalue " + std::to_string(i) + " " + std::to_string(f0) + " -> " + std::to_string(f1) + " -> " +
          std::to_string(f2) + ": the step passed its predicted zero at " + std::to_string(p1 + reach);
    return true;
  }

  /// Acceptance test of a converged continuation step (size h) from the last recorded point to
  /// (xb, pb): the parameter's change within twice max_step, and the eigenvalue-change test of
  /// ContinuationOptions::eigenvalue_change.
  bool accept(const Vector& xb, double pb, double h) {
    if (xs.empty()) return true;
    const double pa = ps.back()[ip()];
    bool ok = true;
    std::string why;
    Params p = ps.back();
    p[ip()] = pb;
    pending_x = Teuchos::null;
    // The corrector can slide along the arclength hyperplane where the branch's tangent is
    // almost all x (a load entering the rod over its first cell): a converged step that moved
    // the parameter by more than twice the largest step is refused, and LOCA halves the step.
    if (std::abs(pb - pa) > 2.0 * std::abs(opt.max_step)) {
      ok = false;
      why = "the parameter moved by " + std::to_string(pb - pa) + ", more than twice max_step";
    }
    if (ok && opt.stability.enabled && opt.eigenvalue_change > 0.0 && stab.back().converged) {
      Stability s = compute_stability(ctx, xb, p, opt.stability);
      if (s.converged) {
        const auto& la = stab.back().eigenvalues;
        const auto& lb = s.eigenvalues;
        const size_t m = std::min({static_cast<size_t>(std::max(stab.back().unstable_modes, s.unstable_modes) + 1),
                                   la.size(), lb.size()});
        const double floor = eigenvalue_floor();
        for (size_t i = 0; i < m && ok; ++i)
          if (std::abs(lb[i] - la[i]) > opt.eigenvalue_change * std::max(std::abs(la[i]), floor)) {
            ok = false;
            why = "eigenvalue " + std::to_string(i) + " " + std::to_string(la[i]) + " -> " + std::to_string(lb[i]) +
                  " (floor " + std::to_string(floor) + ")";
          }
      }
      if (ok && s.converged) ok = !passes_predicted_crossing(s, pb, why);
      if (ok) {
        pending_x = Teuchos::rcp(new Vector(xb, Teuchos::Copy));
        pending_p = pb;
        pending_s = std::move(s);
      }
    }
    if (verbose())
      std::cout << "step " << pa << " -> " << pb << " (h = " << h << ")" << (ok ? " accepted" : " REJECTED: " + why)
                << "\n";
    if (!ok) ++res.rejected_steps;
    return ok;
  }
};

void Recorder::saveSolution(const NOX::Abstract::Vector& x, double pval) {
  const auto& nx = dynamic_cast<const NOX::Thyra::Vector&>(x);
  const Vector& tx = *Extract::getConstTpetraVector(nx.getThyraRCPVector());
  Params p = run_.ctx.model->problem().values;
  p[static_cast<size_t>(run_.opt.parameter)] = pval;
  run_.record(tx, p);
}

LOCA::StatusTest::StatusType StopTest::checkStatus(const LOCA::Abstract::Iterator& stepper,
                                                   LOCA::StatusTest::CheckType) {
  // "Failed" also for a regular stop: with "Finished" the stepper takes one more natural step
  // towards a target value of its own; how the run ended is judged by run_loca. Steps count
  // accepted points; rejected and failed steps are bounded separately.
  status_ = LOCA::StatusTest::NotFinished;
  if (run_.stop_requested || run_.out_of_bounds || stepper.getStepNumber() > run_.opt.max_steps ||
      stepper.getNumFailedSteps() > std::max(100, run_.opt.max_steps))
    status_ = LOCA::StatusTest::Failed;
  return status_;
}

const Vector& tpetra_of(const NOX::Abstract::Vector& v) {
  const auto& nx = dynamic_cast<const NOX::Thyra::Vector&>(v);
  return *Extract::getConstTpetraVector(nx.getThyraRCPVector());
}

/// LOCA's stepper with an acceptance test of every converged step (Run::accept): a rejected
/// step counts as a failed one (LOCA restores the previous point and halves the step).
class GuardedStepper : public LOCA::Stepper {
 public:
  GuardedStepper(const Teuchos::RCP<LOCA::GlobalData>& gd, const Teuchos::RCP<LOCA::MultiContinuation::AbstractGroup>& g,
                 const Teuchos::RCP<LOCA::StatusTest::Abstract>& st, const Teuchos::RCP<NOX::StatusTest::Generic>& nt,
                 const Teuchos::RCP<Teuchos::ParameterList>& p, Run& run)
      : LOCA::Stepper(gd, g, st, nt, p), run_(run) {}

 protected:
  LOCA::Abstract::Iterator::StepStatus postprocess(LOCA::Abstract::Iterator::StepStatus status) override {
    if (status == LOCA::Abstract::Iterator::Successful && !curGroupPtr.is_null()) {
      const auto& xb = dynamic_cast<const LOCA::MultiContinuation::ExtendedVector&>(curGroupPtr->getX());
      if (!run_.accept(tpetra_of(*xb.getXVec()), xb.getScalar(0), stepSize))
        status = LOCA::Abstract::Iterator::Unsuccessful;
    }
    return LOCA::Stepper::postprocess(status);
  }

 private:
  Run& run_;
};

/// The test function of a crossing between points i-1 and i: the eigenvalue omega^2 that
/// changes sign, the k-th smallest with k the smaller unstable-mode count of the two.
double crossing_eigenvalue(const Stability& s, int k) {
  if (!s.converged || k < 0 || static_cast<size_t>(k) >= s.eigenvalues.size())
    return std::numeric_limits<double>::quiet_NaN();
  return s.eigenvalues[static_cast<size_t>(k)];
}

/// The state on the chord hyperplane a . (x - x_{i-1}) = level between points i-1 and i, p
/// free (bordered Newton from x, p); when that fails, again from the nearer bracketing point.
StaticSolveReport solve_on_chord_plane(const Run& run, size_t i, const Vector& a, double level, double c, Vector& x,
                                       Params& p) {
  const ContinuationOptions& opt = run.opt;
  const int ip = static_cast<int>(run.ip());
  const Vector& xa = *run.xs[i - 1];
  StaticSolveReport r = bordered_newton(run.ctx, x, p, ip, a, xa, level, opt.max_newton_iterations + 10,
                                        opt.residual_tolerance, opt.update_tolerance);
  if (r.converged) return r;
  const bool near_a = c < 0.5;
  x.update(1.0, near_a ? xa : *run.xs[i], 0.0);
  p = run.ps[near_a ? i - 1 : i];
  return bordered_newton(run.ctx, x, p, ip, a, xa, level, 2 * opt.max_newton_iterations + 20, opt.residual_tolerance,
                         opt.update_tolerance);
}

/// The located (or bracketed) bifurcation's state, parameter, probes, null vector and type.
void describe_bifurcation(const Run& run, size_t i, const Vector& x, const Params& p, const Stability& s, int k,
                          Bifurcation& b) {
  const auto& P = run.res.points;
  b.parameter = p[run.ip()];
  b.test_function = s.converged ? crossing_eigenvalue(s, k) : std::numeric_limits<double>::quiet_NaN();
  b.null_vector = s.critical_mode;
  b.state = rebased(run.ctx.model->gather(x));
  const rod::StaticModel m = run.ctx.model->problem().model(p);
  for (const auto& pr : run.opt.probes) b.probes.push_back(pr.eval(m, b.state));
  // Fold or pitchfork: at a fold the null vector lies along the branch (the chord across the
  // bracket), at a symmetry-breaking pitchfork it is orthogonal to it. Compared on the
  // frame-independent unknowns r, kappa, n.
  const double cosine = rod::chord_cosine(P[i - 1].state, P[i].state, b.null_vector);
  if (run.verbose()) std::cout << "locate: null vector . chord cosine " << cosine << "\n";
  b.type = cosine > 0.3 ? BifurcationType::fold : BifurcationType::pitchfork;
}

/// Locates the bifurcation between points i-1 and i (see the header): the states on the chord
/// hyperplanes a . (x - x_a) = c |a|^2, a = x_b - x_a, c in (0, 1), p free (bordered Newton),
/// with an Illinois iteration on c for the crossing eigenvalue.
Bifurcation locate(Run& run, size_t i) {
  const StaticContext& ctx = run.ctx;
  const ContinuationOptions& opt = run.opt;
  const auto& P = run.res.points;
  Bifurcation b;
  b.after_point = static_cast<int>(i);
  b.unstable_before = P[i - 1].unstable_modes;
  b.unstable_after = P[i].unstable_modes;
  const int k = std::min(b.unstable_before, b.unstable_after);
  const size_t ip = run.ip();
  const Vector& xa = *run.xs[i - 1];
  const Vector& xb = *run.xs[i];
  Vector a(xa.getMap());
  a.update(1.0, xb, -1.0, xa, 0.0);
  const double aa = a.dot(a);
  const double pa = run.ps[i - 1][ip], pb = run.ps[i][ip];
  double ca = 0.0, cb = 1.0;
  double fa = crossing_eigenvalue(run.stab[i - 1], k), fb = crossing_eigenvalue(run.stab[i], k);
  const double fscale = std::max(std::abs(fa), std::abs(fb));
  Vector x(xa, Teuchos::Copy), best_x(xa, Teuchos::Copy);
  Params p = run.ps[i - 1], best_p = p;
  Stability best_s;
  double c_last = std::numeric_limits<double>::quiet_NaN(), best_c = 0.0;
  double best_f = std::numeric_limits<double>::quiet_NaN();
  bool have = false, c_converged = false;
  const bool bracket = std::isfinite(fa) && std::isfinite(fb) && sign_of(fa) * sign_of(fb) < 0;
  int side = 0;
  for (int it = 0; it < 60; ++it) {
    double c = bracket ? cb - fb * (cb - ca) / (fb - fa) : 0.5 * (ca + cb);
    if (!(c > std::min(ca, cb) && c < std::max(ca, cb))) c = 0.5 * (ca + cb);
    // Guess: the last iterate when there is one, else linear between the bracketing points.
    if (!have) {
      x.update(1.0 - c, xa, c, xb, 0.0);
      p = run.ps[i - 1];
      p[ip] = (1.0 - c) * pa + c * pb;
    } else {
      x.update(1.0, best_x, c - best_c, a, 0.0);
      p = best_p;
    }
    const StaticSolveReport r = solve_on_chord_plane(run, i, a, c * aa, c, x, p);
    if (!r.converged) {
      if (run.verbose()) std::cout << "locate: Newton failed at c = " << c << ": " << r.message << "\n";
      break;
    }
    const Stability s = compute_stability(ctx, x, p, opt.stability);
    const double f = crossing_eigenvalue(s, k);
    if (run.verbose())
      std::cout << "locate: c = " << c << " p = " << p[ip] << " test = " << f << " (" << s.converged << ")\n";
    if (!s.converged || !std::isfinite(f)) break;
    ++b.locate_iterations;
    if (!have || !bracket || std::abs(f) <= std::abs(best_f)) {  // keep the iterate nearest the crossing
      best_x.update(1.0, x, 0.0);
      best_p = p;
      best_s = s;
      best_c = c;
      best_f = f;
    }
    have = true;
    const bool small = std::abs(f) <= 1e-9 * fscale;
    const bool still = std::isfinite(c_last) && std::abs(c - c_last) <= opt.locate_tolerance;
    c_last = c;
    if (bracket) {
      if (sign_of(f) == sign_of(fb)) {
        cb = c;
        fb = f;
        if (side == -1) fa *= 0.5;
        side = -1;
      } else {
        ca = c;
        fa = f;
        if (side == 1) fb *= 0.5;
        side = 1;
      }
    } else {
      // No sign change of the test function: bisect on the unstable-mode count.
      if (s.unstable_modes == b.unstable_after) cb = c;
      else ca = c;
    }
    if (small || still) {
      c_converged = still;
      break;
    }
  }
  // Located: the crossing eigenvalue at the reported state is below 1e-5 of its values at the
  // bracketing points (the iteration ends when it is below 1e-9, when c stops moving, or when a
  // solve fails - near the singular point with an iterative linear solver on several ranks);
  // without a sign change, when the bisection on the mode count has converged.
  if (have) b.located = bracket ? std::abs(best_f) <= 1e-5 * fscale : c_converged;
  if (!have) {  // fall back to the bracketing point
    best_x.update(1.0, xb, 0.0);
    best_p = run.ps[i];
  }
  describe_bifurcation(run, i, best_x, best_p, best_s, k, b);
  return b;
}

void detect(Run& run) {
  const auto& P = run.res.points;
  for (size_t i = 1; i < P.size(); ++i) {
    if (P[i - 1].unstable_modes < 0 || P[i].unstable_modes < 0) continue;
    if (P[i - 1].unstable_modes == P[i].unstable_modes) continue;
    auto inside = [&](double v) { return v >= run.opt.min_value && v <= run.opt.max_value; };
    if (!inside(P[i - 1].parameter) || !inside(P[i].parameter)) continue;  // a jump past a bound
    if (run.opt.locate_bifurcations) {
      run.res.bifurcations.push_back(locate(run, i));
    } else {
      Bifurcation b;
      b.after_point = static_cast<int>(i);
      b.unstable_before = P[i - 1].unstable_modes;
      b.unstable_after = P[i].unstable_modes;
      b.parameter = P[i].parameter;
      b.probes = P[i].probes;
      b.state = P[i].state;
      const bool turn = i >= 2 && sign_of(P[i].parameter - P[i - 1].parameter) != sign_of(P[i - 1].parameter - P[i - 2].parameter);
      b.type = turn ? BifurcationType::fold : BifurcationType::pitchfork;
      run.res.bifurcations.push_back(b);
    }
  }
}

Teuchos::RCP<NOX::StatusTest::Generic> newton_tests(const ContinuationOptions& opt) {
  auto normf = Teuchos::rcp(new NOX::StatusTest::NormF(opt.residual_tolerance, NOX::Abstract::Vector::MaxNorm,
                                                       NOX::StatusTest::NormF::Unscaled));
  auto wrms = Teuchos::rcp(new NOX::StatusTest::NormWRMS(opt.update_tolerance, opt.update_tolerance));
  auto conv = Teuchos::rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::AND, normf, wrms));
  auto tests = Teuchos::rcp(new NOX::StatusTest::Combo(NOX::StatusTest::Combo::OR));
  tests->addStatusTest(Teuchos::rcp(new NOX::StatusTest::FiniteValue));
  tests->addStatusTest(conv);
  tests->addStatusTest(Teuchos::rcp(new NOX::StatusTest::MaxIters(opt.max_newton_iterations)));
  return tests;
}

void run_loca(Run& run, const Vector& x0) {
  const ContinuationOptions& opt = run.opt;
  const StaticContext& ctx = run.ctx;
  const Params& p0 = ctx.model->problem().values;
  const std::string name = rod::parameter_name(opt.parameter);
  auto top = Teuchos::rcp(new Teuchos::ParameterList);
  Teuchos::ParameterList& loca = top->sublist("LOCA");
  Teuchos::ParameterList& st = loca.sublist("Stepper");
  st.set("Continuation Method", opt.method);
  st.set("Continuation Parameter", name);
  st.set("Initial Value", p0[static_cast<size_t>(opt.parameter)]);
  st.set("Max Value", std::isfinite(opt.max_value) ? opt.max_value : 1e300);
  st.set("Min Value", std::isfinite(opt.min_value) ? opt.min_value : -1e300);
  st.set("Max Steps", opt.max_steps);
  st.set("Max Nonlinear Iterations", opt.max_newton_iterations);
  st.set("Compute Eigenvalues", false);
  // No automatic rescaling of the parameter in the arclength: it explodes where dp/ds ~ 0
  // (on a branch leaving a pitchfork). The arclength is sqrt(|dx|^2 / n + dp^2).
  st.set("Enable Arc Length Scaling", false);
  loca.sublist("Predictor").set("Method", std::string("Tangent"));
  Teuchos::ParameterList& ss = loca.sublist("Step Size");
  ss.set("Method", std::string("Adaptive"));
  ss.set("Initial Step Size", opt.initial_step);
  ss.set("Min Step Size", opt.min_step);
  ss.set("Max Step Size", opt.max_step);
  ss.set("Aggressiveness", opt.step_aggressiveness);
  Teuchos::ParameterList& nox = top->sublist("NOX");
  nox.set("Nonlinear Solver", std::string("Line Search Based"));
  nox.sublist("Line Search").set("Method", std::string("Full Step"));
  nox.sublist("Direction").set("Method", std::string("Newton"));
  nox.sublist("Direction").sublist("Newton").sublist("Linear Solver").set("Tolerance", 1e-12);
  const int quiet = NOX::Utils::Error;
  const int loud = NOX::Utils::Error | NOX::Utils::Warning | NOX::Utils::StepperIteration;
  nox.sublist("Printing").set("Output Information", opt.verbose ? loud : quiet);
  // LOCA prints its final status-test summary whatever the print level: send the normal
  // output stream to a black hole unless asked to be verbose (errors still reach stderr).
  if (!opt.verbose)
    nox.sublist("Printing").set<Teuchos::RCP<std::ostream>>("Output Stream", Teuchos::rcp(new Teuchos::oblackholestream));
  auto gd = LOCA::createGlobalData(top);
  try {
    LOCA::ParameterVector pv;
    for (int q = 0; q < rod::num_static_parameters; ++q)
      pv.addParameter(rod::parameter_name(static_cast<rod::StaticParameter>(q)), p0[static_cast<size_t>(q)]);
    auto xt = Thyra::createVector(Teuchos::rcp(new Vector(x0, Teuchos::Copy)), ctx.model->get_x_space());
    NOX::Thyra::Vector nx(xt);
    // implement_dfdp: LOCA takes dF/dp from the model (analytic) instead of differencing F.
    auto grp = Teuchos::rcp(new LOCA::Thyra::Group(gd, nx, ctx.model, pv, 0, true));
    grp->setSaveDataStrategy(Teuchos::rcp(new Recorder(run)));
    auto stop = Teuchos::rcp(new StopTest(run));
    GuardedStepper stepper(gd, grp, stop, newton_tests(opt), top, run);
    const LOCA::Abstract::Iterator::IteratorStatus status = stepper.run();
    if (run.stop_requested) {
      run.res.completed = true;
      run.res.message = "stopped by the stop callback";
    } else if (run.out_of_bounds) {
      run.res.completed = true;
      run.res.message = "parameter bound reached";
    } else if (status == LOCA::Abstract::Iterator::Finished) {
      run.res.completed = true;
      run.res.message = "finished";
    } else if (stepper.getStepNumber() > opt.max_steps) {
      run.res.completed = true;
      run.res.message = "maximum number of steps reached";
    } else {
      run.res.message = "LOCA stepper failed (step size below minimum or Newton failure)";
    }
  } catch (const std::exception& e) {
    run.res.message = std::string("LOCA stepper failed: ") + e.what();
  }
  LOCA::destroyGlobalData(gd);
}

}  // namespace

ContinuationResult continue_(const rod::StaticProblem& problem, const std::vector<rod::StaticNode>& start,
                             const ContinuationOptions& options, const Comm& comm, const PointCallback& on_point) {
  ContinuationResult res;
  res.parameter = rod::parameter_name(options.parameter);
  res.parameter_unit = rod::parameter_unit(options.parameter);
  for (const auto& pr : options.probes) {
    res.probe_names.push_back(pr.name);
    res.probe_units.push_back(pr.unit);
  }
  res.final_problem = problem;
  StaticContext ctx(problem, rebased(start), comm, options.solver);
  Vector x(*ctx.model->nominal_x(), Teuchos::Copy);
  Params p = problem.values;
  const StaticSolveReport r0 = fixed_parameter_solve(ctx, x, p, options.max_newton_iterations + 10,
                                                     options.residual_tolerance, options.update_tolerance);
  if (!r0.converged) {
    res.message = "the start state does not converge: " + r0.message;
    return res;
  }
  Run run(ctx, options, on_point, res);
  run_loca(run, x);
  if (run.landing_failed) res.message += "; could not land on the bound (the last point lies beyond it)";
  if (options.detect_bifurcations && options.stability.enabled) detect(run);
  if (!res.points.empty()) res.final_problem.value(options.parameter) = res.points.back().parameter;
  return res;
}

StaticSolveReport static_solve(const rod::StaticProblem& problem, std::vector<rod::StaticNode>& state, const Comm& comm,
                               const Teuchos::ParameterList& solver) {
  StaticContext ctx(problem, rebased(state), comm, solver);
  Vector x(*ctx.model->nominal_x(), Teuchos::Copy);
  Params p = problem.values;
  StaticSolveReport r = fixed_parameter_solve(ctx, x, p, 40, 1e-9, 1e-10);
  if (r.converged) state = rebased(ctx.model->gather(x));
  return r;
}

Stability static_stability(const rod::StaticProblem& problem, const std::vector<rod::StaticNode>& state,
                           const Comm& comm, const StabilityOptions& options, const Teuchos::ParameterList& solver) {
  StaticContext ctx(problem, rebased(state), comm, solver);
  return compute_stability(ctx, *ctx.model->nominal_x(), problem.values, options);
}

ContinuationResult switch_branch(const rod::StaticProblem& problem, const Bifurcation& pf, double amplitude,
                                 const ContinuationOptions& options, const Comm& comm, const PointCallback& on_point) {
  if (pf.null_vector.size() != pf.state.size() || pf.state.empty())
    throw std::invalid_argument("switch_branch: the bifurcation has no state or null vector");
  rod::StaticProblem pb = problem;
  pb.value(options.parameter) = pf.parameter;
  StaticContext ctx(pb, pf.state, comm, options.solver);
  const Vector& xs = *ctx.model->nominal_x();
  Vector a(xs.getMap()), x(xs, Teuchos::Copy);
  std::vector<rod::StaticNode> phi = pf.state;
  for (size_t j = 0; j < phi.size(); ++j) phi[j].x = pf.null_vector[j];
  ctx.model->scatter(phi, a);
  x.update(amplitude, a, 1.0);
  Params p = pb.values;
  const double c = amplitude * a.dot(a);
  const StaticSolveReport r = bordered_newton(ctx, x, p, static_cast<int>(options.parameter), a, xs, c,
                                              options.max_newton_iterations + 10, options.residual_tolerance,
                                              options.update_tolerance);
  if (!r.converged) {
    ContinuationResult res;
    res.parameter = rod::parameter_name(options.parameter);
    res.message = "branch switching: no solution with the perturbation amplitude fixed: " + r.message;
    return res;
  }
  rod::StaticProblem pn = pb;
  pn.values = p;
  ContinuationOptions o = options;
  const double dp = p[static_cast<size_t>(options.parameter)] - pf.parameter;
  o.initial_step = (dp < 0.0 ? -1.0 : 1.0) * std::abs(options.initial_step);
  return continue_(pn, ctx.model->gather(x), o, comm, on_point);
}

double continuation_bytes_per_node() { return 70000.0; }

}  // namespace traverse::solver
