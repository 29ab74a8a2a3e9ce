// A dynamic rod run in stages (docs/developer.md, "Module map"):
//   model (rod_setup: build_rod_model) -> initial state (rod_setup: initial_state, each rank
//   its piece) -> stepper and path -> output plan (RodOutputs) -> time loop (RodTimeLoop) ->
//   report.
// Each stage is a function or a class of its own; run_rod only strings them together.
#include <mpi.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>
#include <sstream>

#include "interrupt.hpp"
#include "progress.hpp"
#include "rod_adaptive.hpp"
#include "rod_quantities.hpp"
#include "restart.hpp"
#include "rod_setup.hpp"
#include "traverse/solver/linear_solver_choice.hpp"
#include "traverse/output/restart.hpp"
#include "run.hpp"
#include "run_beam_coupled.hpp"
#include "run_rod_coupled.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/solver/rod_stepper.hpp"
#include "traverse/core/comm.hpp"
#include "traverse/version.hpp"
#include "solver_access.hpp"

namespace traverse::app {

namespace {

/// The adaptive estimate's quantities of this rank's owned nodes, now.
std::vector<rod::NodeLevel> owned_levels(const solver::RodStepper& st) {
  std::vector<rod::NodeLevel> y(static_cast<size_t>(st.num_owned_nodes()));
  for (int k = 0; k < st.num_owned_nodes(); ++k) y[static_cast<size_t>(k)] = rod::node_level(st.owned_node(k));
  return y;
}

/// A load that crosses more than one cell per time step is resolved by the space grid but
/// not in time: the run goes on (it converges as dt falls), with a warning naming the keys.
void warn_under_resolved_loads(const scene::Scene& sc, const TimeGrid& g) {
  const double ds = sc.mesh.ds;
  for (const auto& l : sc.loads) {
    const double t_leave = std::min(g.t_end, l.exit_time(sc.rod.length));
    const double v = std::max(std::abs(l.velocity(l.entry_time)), std::abs(l.velocity(std::max(l.entry_time, t_leave))));
    if (v > 0.0 && g.dt * v > ds * (1.0 + 1e-9))
      std::fprintf(stderr,
                   "traverse: warning: %s: time.dt = %.6g s moves load '%s' (up to %.6g m/s) %.3g cells per step "
                   "(mesh.ds = %.6g m): its path is under-resolved in time (time.dt: auto gives ds / v)\n",
                   sc.file.c_str(), g.dt, l.name.c_str(), v, g.dt * v / ds, ds);
  }
}

/// The position of the rod's left end: fixed for ends that hold it, else integrated in time
/// from its velocity R^T u (trapezoidal, second order).
class LeftEnd {
 public:
  LeftEnd(const solver::RodStepper& st, bool moves, const Vec3& r0, MPI_Comm comm)
      : st_(st), moves_(moves), r0_(r0), comm_(comm) {}
  const Vec3& position() const { return r0_; }
  void set_position(const Vec3& r) { r0_ = r; }
  /// Call before a step of length h, then after_step(h).
  void before_step() { v_old_ = moves_ ? velocity() : Vec3::Zero(); }
  void after_step(double h) {
    if (moves_) r0_ = rod::trapezoidal_step(r0_, v_old_, velocity(), h);
  }

 private:
  Vec3 velocity() const {  // R^T u at node 0, broadcast from its owner
    Vec3 v = Vec3::Zero();
    int root = 0;
    if (st_.first_owned_node() == 0) v = rod::fixed_velocity(st_.owned_node(0));
    const int owner = st_.first_owned_node() == 0 ? par::rank(comm_) : 0;
    par::allreduce(&owner, &root, 1, MPI_INT, MPI_MAX, comm_);
    par::bcast(v.data(), 3, MPI_DOUBLE, root, comm_);
    return v;
  }
  const solver::RodStepper& st_;
  bool moves_;
  Vec3 r0_, v_old_ = Vec3::Zero();
  MPI_Comm comm_;
};

/// The outputs of a rod run: the scene's probes and fields plus each load's position,
/// declared in the output file and evaluated at an output step.
class RodOutputs {
 public:
  RodOutputs(const scene::Scene& sc, const rod::RodModel& model, const solver::RodStepper& st, MPI_Comm comm);
  /// Names as the output file holds them, in declaration order (a restart's copy).
  std::vector<std::string> probe_names() const;
  std::vector<std::string> field_names() const;
  output::NodeLayout layout() const;
  void declare(output::Writer& w) const;
  void write(output::Writer& w, double t, const Vec3& r0);

 private:
  void evaluate_probes(const std::vector<rod::RodNode>& near, const std::vector<Vec3>& near_r);
  void evaluate_fields(const std::vector<Vec3>& r);
  std::vector<Vec3> owned_centreline(const Vec3& r0) const;
  std::vector<Vec3> near_positions(const std::vector<Vec3>& r) const;
  const scene::Scene& sc_;
  const rod::RodModel& model_;
  const solver::RodStepper& st_;
  MPI_Comm comm_;
  int num_cells_, first_, count_;
  rod::OutputNeeds needs_;
  std::vector<std::vector<double>> probe_values_, field_values_;
  std::vector<double> sigma_;
};

RodOutputs::RodOutputs(const scene::Scene& sc, const rod::RodModel& model, const solver::RodStepper& st,
                       MPI_Comm comm)
    : sc_(sc), model_(model), st_(st), comm_(comm), num_cells_(sc.mesh.nodes - 1), first_(st.first_owned_node()),
      count_(st.num_owned_nodes()) {
  // What the outputs read at an output step: the nodes around the probes, and the centreline
  // (each rank its own nodes) only for a position probe or the field r.
  std::vector<rod::PointOutput> points;
  for (const auto& pr : sc.output.probes) points.push_back({pr.at, pr.quantity == scene::Quantity::position});
  bool r_field = false;
  for (const auto f : sc.output.fields) r_field = r_field || f == scene::Field::r;
  needs_ = rod::output_needs(num_cells_, sc.mesh.ds, points, r_field);
  probe_values_.assign(sc.output.probes.size() + sc.loads.size(), std::vector<double>(1));
  for (size_t i = 0; i < sc.output.probes.size(); ++i) probe_values_[i].assign(3, 0.0);
  field_values_.resize(sc.output.fields.size());
  sigma_.assign(std::max<size_t>(1, sc.loads.size()), std::numeric_limits<double>::quiet_NaN());
}

std::vector<std::string> RodOutputs::probe_names() const {
  std::vector<std::string> names;
  for (const auto& pr : sc_.output.probes) names.push_back(pr.name);
  for (const auto& l : sc_.loads) names.push_back(l.name + "_position");
  return names;
}

std::vector<std::string> RodOutputs::field_names() const {
  std::vector<std::string> names;
  for (const auto f : sc_.output.fields) names.push_back(scene::name_of(f));
  return names;
}

output::NodeLayout RodOutputs::layout() const {
  output::NodeLayout layout;
  layout.global_count = static_cast<size_t>(num_cells_ + 1);
  layout.first = static_cast<size_t>(first_);
  layout.count = static_cast<size_t>(count_);
  for (int k = 0; k < count_; ++k) layout.s.push_back((first_ + k) * sc_.mesh.ds);
  return layout;
}

void RodOutputs::declare(output::Writer& w) const {
  declare_rod_probes(w, sc_.output.probes);
  for (const auto& l : sc_.loads)
    w.add_probe({l.name + "_position", 1, "m", "arclength sigma(t) of load '" + l.name + "'", {}});
  for (const auto f : sc_.output.fields) {
    const RodFieldInfo fi = rod_field_info(f);
    w.add_field({scene::name_of(f), fi.components, fi.units, fi.description, fi.component_names, fi.geometry});
  }
}

void RodOutputs::evaluate_probes(const std::vector<rod::RodNode>& near, const std::vector<Vec3>& near_r) {
  auto view = [&](int j) {
    const auto i = static_cast<size_t>(std::lower_bound(needs_.nodes.begin(), needs_.nodes.end(), j) - needs_.nodes.begin());
    return node_view(near[i], near_r.empty() ? Vec3::Zero() : near_r[i]);
  };
  for (size_t i = 0; i < sc_.output.probes.size(); ++i) {
    const auto& pr = sc_.output.probes[i];
    const Vec3 v = quantity_at(pr.quantity, pr.at, sc_.mesh.ds, num_cells_, model_.props, pr.frame, view);
    probe_values_[i].assign(v.data(), v.data() + 3);
  }
}

void RodOutputs::evaluate_fields(const std::vector<Vec3>& r) {
  for (size_t f = 0; f < sc_.output.fields.size(); ++f) {
    const scene::Field field = sc_.output.fields[f];
    auto& out = field_values_[f];
    const size_t comps = field == scene::Field::R ? 9 : 3;
    out.resize(comps * static_cast<size_t>(count_));
    for (int k = 0; k < count_; ++k) {
      const auto& nd = st_.owned_node(k);
      double* o = out.data() + comps * static_cast<size_t>(k);
      if (field == scene::Field::R) {
        for (int i = 0; i < 3; ++i)
          for (int c = 0; c < 3; ++c) o[3 * i + c] = nd.R(i, c);
      } else {
        const Vec3 p = field == scene::Field::r ? r[static_cast<size_t>(k)] : Vec3::Zero();
        const Vec3 v = quantity_value(field_quantity(field), node_view(nd, p), model_.props, scene::Frame::body);
        std::copy(v.data(), v.data() + 3, o);
      }
    }
  }
}

// The centreline at this rank's nodes from r(0) = r0: each rank sums up its piece, the
// summaries of all ranks give each its start (rod::centreline_starts), and it integrates its
// own nodes from there.
std::vector<Vec3> RodOutputs::owned_centreline(const Vec3& r0) const {
  std::vector<Vec3> t(static_cast<size_t>(count_));
  for (int k = 0; k < count_; ++k) t[static_cast<size_t>(k)] = rod::tangent(st_.owned_node(k));
  const rod::CentrelinePiece mine = rod::centreline_piece(t, first_, model_.ds(), first_ == 0 ? r0 : Vec3::Zero());
  const int rank = par::rank(comm_);
  std::vector<rod::CentrelinePiece> all(static_cast<size_t>(par::size(comm_)));
  par::allgather_bytes(&mine, sizeof mine, all.data(), comm_);
  return rod::centreline_from(t, model_.ds(), rod::centreline_starts(all, model_.ds(), r0)[static_cast<size_t>(rank)]);
}

// r at the nodes the probes read (needs_.nodes), on every rank, from their owners' `r`.
std::vector<Vec3> RodOutputs::near_positions(const std::vector<Vec3>& r) const {
  const std::vector<int>& wanted = needs_.nodes;
  std::vector<double> local(3 * wanted.size(), 0.0), all(local.size());
  for (size_t i = 0; i < wanted.size(); ++i)
    if (wanted[i] >= first_ && wanted[i] < first_ + count_) {
      const Vec3& p = r[static_cast<size_t>(wanted[i] - first_)];
      std::copy(p.data(), p.data() + 3, &local[3 * i]);
    }
  par::allreduce(local.data(), all.data(), static_cast<int>(local.size()), MPI_DOUBLE, MPI_SUM, comm_);
  std::vector<Vec3> out(wanted.size());
  for (size_t i = 0; i < wanted.size(); ++i) out[i] = Vec3(all[3 * i], all[3 * i + 1], all[3 * i + 2]);
  return out;
}

void RodOutputs::write(output::Writer& w, double t, const Vec3& r0) {
  std::vector<Vec3> r, near_r;     // r at the owned nodes and at needs_.nodes (with the centreline)
  std::vector<rod::RodNode> near;  // needs_.nodes
  if (needs_.centreline) r = owned_centreline(r0);
  if (!needs_.nodes.empty()) {
    near = gather_nodes(st_, needs_.nodes, comm_);
    if (needs_.centreline) near_r = near_positions(r);
  }
  evaluate_probes(near, near_r);
  for (size_t i = 0; i < sc_.loads.size(); ++i) {
    sigma_[i] = sc_.loads[i].sigma(t);
    probe_values_[sc_.output.probes.size() + i][0] = sigma_[i];
  }
  evaluate_fields(r);
  std::vector<output::DoubleView> views(field_values_.begin(), field_values_.end());
  w.write_step(t, sigma_, probe_values_, views);
}

/// Values per node of a rod run's restart point: the node, and with time.adaptive the
/// controller's two earlier levels.
std::size_t restart_components(const scene::Scene& sc) {
  return rod::kPackedNodeValues + (sc.time.adaptive.enabled ? RodAdaptiveControl::kPerNode : 0);
}

/// Restart points of a rod run (docs/reliability.md): the state, the time, the step index
/// (adaptive: the accepted steps) and extra = (left-end position, dt, path, and with
/// time.adaptive the controller's scalars).
class RodRestartPoints {
 public:
  RodRestartPoints(const solver::RodStepper& st, output::Writer& w, double dt, bool planar, double interval,
                   const RodAdaptiveControl* adaptive, MPI_Comm comm)
      : st_(st), w_(w), dt_(dt), planar_(planar), interval_(interval), adaptive_(adaptive), comm_(comm),
        components_(rod::kPackedNodeValues + (adaptive ? RodAdaptiveControl::kPerNode : 0)),
        slots_(comm, components_, static_cast<std::size_t>(st.first_owned_node())),
        packed_(components_ * static_cast<std::size_t>(st.num_owned_nodes())), last_(std::chrono::steady_clock::now()) {}
  /// Stores the point of time step i (once per step).
  void store(long i, const Vec3& r0) {
    if (i == stored_at_) return;
    for (int k = 0; k < st_.num_owned_nodes(); ++k) {
      double* o = &packed_[components_ * static_cast<std::size_t>(k)];
      rod::pack_node(st_.owned_node(k), o);
      if (adaptive_) adaptive_->pack_node(k, o + rod::kPackedNodeValues);
    }
    std::vector<double> extra = {r0.x(), r0.y(), r0.z(), dt_, planar_ ? 1.0 : 0.0};
    if (adaptive_)
      for (const double v : adaptive_->pack_scalars()) extra.push_back(v);
    slots_.write(w_, st_.time(), i, extra, packed_);
    stored_at_ = i;
    last_ = std::chrono::steady_clock::now();
  }
  /// Whether the restart interval has passed since the last point (rank 0's clock decides).
  bool due() const { return restart_due(last_, interval_, comm_); }

 private:
  const solver::RodStepper& st_;
  output::Writer& w_;
  double dt_;
  bool planar_;
  double interval_;
  const RodAdaptiveControl* adaptive_;
  MPI_Comm comm_;
  std::size_t components_;
  output::RestartSlots slots_;
  std::vector<double> packed_;
  long stored_at_ = -1;
  std::chrono::steady_clock::time_point last_;
};

/// ", N solves retried from the other initial guess" (solver key 'Initial Guess: auto'), or "".
std::string retries_note(long retries) {
  if (retries == 0) return "";
  return ", " + std::to_string(retries) + (retries == 1 ? " solve" : " solves") + " retried from the other initial guess";
}

/// Counters of the time loop, for the final report.
struct LoopTotals {
  long newton = 0, solves = 0;
  long guess_retries = 0;  ///< solves that failed from the blended guess and were redone from the old level
  long last_step = 0;  ///< index of the last time step taken
  double seconds = 0.0;
};

/// What both time loops work on, and their common ends: a stop on a signal and the planar
/// path's loss (each stores a restart point, sets the file's status and throws).
struct RodLoopParts {
  solver::RodStepper& st;
  RodOutputs& out;
  output::Writer& w;
  RodRestartPoints& rp;
  LeftEnd& left;
  const TimeGrid& g;
  int every;
  const RunOptions& opt;
  MPI_Comm comm;
  /// `where`, e.g. "time step 12 of 100"; the restart point is that of `step`.
  [[noreturn]] void interrupt(long step, const std::string& where, int sig, Progress& progress) const {
    stop_interrupted_run(sig, st.time(), where, w, opt.output, progress, [&] { rp.store(step, left.position()); });
  }
  /// The state is that of `step` (before the step that lost planarity).
  [[noreturn]] void fail_planar(long step, const std::string& what, Progress& progress) const {
    progress.done();
    const std::string msg = what + "; traverse run --restart " + opt.output +
                            " --set scheme.planar=off continues on the 3D path";
    rp.store(step, left.position());
    w.fail(msg);
    throw NumericsError(msg);
  }
};

/// The time loop: steps, output steps, restart points, interrupts and failures.
class RodTimeLoop {
 public:
  RodTimeLoop(const RodLoopParts& parts, const LoadRatio& load) : p_(parts), load_(load) {}
  LoopTotals run(long first_step, bool show_progress);

 private:
  [[noreturn]] void fail_step(long i, double t0, const solver::StepFailure& e, Progress& progress);
  RodLoopParts p_;
  LoadRatio load_;
};

void RodTimeLoop::fail_step(long i, double t0, const solver::StepFailure& e, Progress& progress) {
  progress.done();
  std::ostringstream os;
  os << "time step " << i << " of " << p_.g.steps << " (t = " << e.time() << " s, dt = " << e.step()
     << " s) failed after halving it " << e.depth() << " times: " << e.report().status << " (residual ";
  // A norm is >= 0: NOX reports a non-finite residual as a huge negative number.
  const double residual = e.report().residual_norm;
  if (residual >= 0.0 && std::isfinite(residual)) os << residual;
  else os << "not finite";
  os << "); ";
  // A step far shorter than the time a bending wave needs to cross a cell: the residual's
  // 1/dt terms round above the absolute residual tolerance, so a smaller dt cannot help. The
  // step is time.dt, or the last one, shortened to end at time.end.
  const auto& props = p_.st.model().props;
  const double ds = p_.st.model().ds(), cell_time = ds * ds * std::sqrt(props.rhoA / props.bending_stiffness());
  const double h = e.step();
  const bool last = i == p_.g.steps && h < p_.g.dt * (1.0 - 1e-6);
  if (h < 1e-6 * cell_time) {
    os << (last ? "the last step, to time.end = " + scene::format_number(p_.g.t_end) + " s, is "
                : "time.dt = " + scene::format_number(p_.g.dt) + " s is ")
       << cell_time / h << " times shorter than a bending wave needs to cross a cell (mesh.ds^2 sqrt(rho A / (E I)) = "
       << cell_time << " s), where the rounding of the 1/dt terms keeps the residual above 'Residual Tolerance': try "
       << (!last ? "a larger time.dt (auto: mesh.ds / the fastest loads.*.speed)"
           : p_.g.steps == 1 ? "a larger time.end" : "a time.end that is a whole number of time.dt steps")
       << " or a larger 'Residual Tolerance' in solver";
  } else {
    os << "try scheme.rho_inf < 1, a smaller time.dt, or a larger 'Max Subdivision Depth' in solver";
  }
  // A load the rod can hardly carry: say so, with the keys (the static start's criterion).
  if (load_.ratio > 1e5)
    os << "; the load ratio W L^2 / (E I) = " << load_.ratio << " is large (W = " << load_.W << " N from " << load_.what
       << ", E I = " << load_.EI << " N m^2 from rod.youngs_modulus and rod.section): a smaller load or a stiffer rod "
       << "may be needed";
  os << " (traverse run --restart " << p_.opt.output << " --set ... continues from t = " << t0 << " s)";
  p_.rp.store(i - 1, p_.left.position());  // the stepper kept the state before the failed step
  p_.w.fail(os.str());
  throw NumericsError(os.str());
}

LoopTotals RodTimeLoop::run(long first_step, bool show_progress) {
  Progress progress(show_progress, "t", "s", p_.st.time(), p_.g.t_end, p_.opt.progress_interval);
  LoopTotals tot;
  tot.last_step = first_step - 1;
  const auto start = std::chrono::steady_clock::now();
  for (long i = first_step; i <= p_.g.steps; ++i) {
    // Step i ends at the grid time i dt (t_end for the last): computed from i, not accumulated,
    // so the stepper's time (t0 + h, exact) stays on the grid and the run takes the steps it
    // reported (core/time_grid.hpp bounds the rounding of i dt).
    const double t0 = p_.st.time();
    const double h = p_.g.time(i) - t0;
    if (!(h > 0.0))
      throw std::logic_error("rod time loop: step " + std::to_string(i) + " of " + std::to_string(p_.g.steps) +
                             " has length " + std::to_string(h) + " s (t = " + std::to_string(t0) + " s)");
    p_.left.before_step();
    try {
      const auto rep = p_.st.step(h);
      tot.newton += rep.newton_iterations;
      tot.solves += rep.substeps;
      tot.guess_retries += rep.guess_retries;
    } catch (const solver::StepFailure& e) {
      fail_step(i, t0, e, progress);
    } catch (const solver::PlanarityLost& e) {
      p_.fail_planar(i - 1, "time step " + std::to_string(i) + " of " + std::to_string(p_.g.steps) + ": " + e.what(),
                     progress);
    }
    p_.left.after_step(h);
    tot.last_step = i;
    if (i % p_.every == 0 || i == p_.g.steps) {
      p_.out.write(p_.w, p_.st.time(), p_.left.position());
      if (p_.rp.due()) p_.rp.store(i, p_.left.position());
    }
    progress.update(p_.st.time(), i);
    if (const int sig = i < p_.g.steps ? interrupt_requested(p_.comm) : 0)
      p_.interrupt(i, "time step " + std::to_string(i) + " of " + std::to_string(p_.g.steps), sig, progress);
  }
  progress.done();
  tot.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return tot;
}

/// The adaptive time loop (time.adaptive, docs/adaptive.md): each step's length comes from
/// the error estimate; the steps land on the output times of the fixed-dt grid (every
/// output.every steps of time.dt, and time.end), so outputs compare point for point with a
/// fixed-dt run. The first step of a run, without the three levels the extrapolation estimate
/// needs, is checked by step doubling.
class RodAdaptiveLoop {
 public:
  /// `loads`: the scene's; the steps land on their node crossings (next_node_crossing).
  RodAdaptiveLoop(const RodLoopParts& parts, RodAdaptiveControl& ctl, const std::vector<scene::MovingLoadSpec>& loads,
                  bool land_on_nodes)
      : p_(parts), ctl_(ctl), loads_(loads), land_(land_on_nodes) {}
  LoopTotals run(bool show_progress);

 private:
  double output_time(long k) const { return p_.g.time(std::min(k * static_cast<long>(p_.every), p_.g.steps)); }
  /// One Newton solve of h; false (the state unchanged, failure_ set) when it did not converge.
  bool try_step(double h, solver::StepReport& rep, Progress& progress);
  bool extrapolated_step(double h, Progress& progress);
  bool doubled_step(double h, Progress& progress);
  /// A failed or rejected step of length h (the state as before it): the next try, or the
  /// end of the run at dt_min.
  void retry_smaller(double h, double next, const std::string& why, Progress& progress);
  [[noreturn]] void fail(const std::string& why, Progress& progress);
  RodLoopParts p_;
  RodAdaptiveControl& ctl_;
  const std::vector<scene::MovingLoadSpec>& loads_;
  bool land_;
  LoopTotals tot_;
  std::string failure_;  ///< why the last try_step failed
};

void RodAdaptiveLoop::fail(const std::string& why, Progress& progress) {
  progress.done();
  std::ostringstream os;
  os.precision(12);
  os << "adaptive time stepping (time.adaptive) at t = " << p_.st.time() << " s: " << why
     << "; try a larger time.adaptive.tolerance or dt_min, or scheme.rho_inf < 1 (traverse run --restart "
     << p_.opt.output << " --set ... continues from t = " << p_.st.time() << " s)";
  p_.rp.store(ctl_.totals().accepted, p_.left.position());  // the state before the failed step
  p_.w.fail(os.str());
  throw NumericsError(os.str());
}

void RodAdaptiveLoop::retry_smaller(double h, double next, const std::string& why, Progress& progress) {
  const double dt_min = ctl_.controller().parameters().dt_min;
  if (h <= dt_min * (1.0 + 1e-12)) {
    std::ostringstream os;
    os << why << " at the smallest step, time.adaptive.dt_min = " << dt_min << " s";
    fail(os.str(), progress);
  }
  ctl_.next_dt = std::min(next, h);
}

bool RodAdaptiveLoop::try_step(double h, solver::StepReport& rep, Progress& progress) {
  bool ok = false;
  try {
    ok = p_.st.try_step(h, rep);
  } catch (const solver::PlanarityLost& e) {
    p_.fail_planar(ctl_.totals().accepted, e.what(), progress);
  }
  tot_.newton += rep.newton_iterations;
  ++tot_.solves;
  tot_.guess_retries += rep.guess_retries;
  if (!ok) {
    ++ctl_.totals().failed;
    std::ostringstream os;
    os << "the Newton solve of a step of dt = " << h << " s did not converge (" << p_.st.last_newton_report().status << ")";
    failure_ = os.str();
  }
  return ok;
}

bool RodAdaptiveLoop::extrapolated_step(double h, Progress& progress) {
  p_.left.before_step();
  solver::StepReport rep;
  if (!try_step(h, rep, progress)) {
    retry_smaller(h, ctl_.controller().after_failure(h), failure_, progress);
    return false;
  }
  std::vector<rod::NodeLevel> y = owned_levels(p_.st);
  const double err = ctl_.extrapolation_error(y, h);
  const StepDecision d = ctl_.controller().decide(h, err, rep.newton_iterations);
  if (!d.accept) {
    p_.st.undo_step();
    ++ctl_.totals().rejected;
    std::ostringstream os;
    os << "the error estimate is " << err << " times the tolerance";
    retry_smaller(h, d.next_dt, os.str(), progress);
    return false;
  }
  p_.left.after_step(h);
  ctl_.accept(std::move(y), h);
  ctl_.totals().record_accepted(h);
  ctl_.next_dt = d.next_dt;
  return true;
}

bool RodAdaptiveLoop::doubled_step(double h, Progress& progress) {
  const rod::RodState saved = p_.st.ghosted_piece();
  const Vec3 r_saved = p_.left.position();
  auto restore = [&] {
    p_.st.set_state(saved, p_.st.first_ghosted_node());
    p_.left.set_position(r_saved);
  };
  solver::StepReport rep;
  if (!try_step(h, rep, progress)) {
    retry_smaller(h, ctl_.controller().after_failure(h), failure_, progress);
    return false;
  }
  const std::vector<rod::NodeLevel> full = owned_levels(p_.st);
  p_.st.undo_step();
  std::vector<rod::NodeLevel> mid, half;
  int newton = rep.newton_iterations;
  for (int part = 0; part < 2; ++part) {
    p_.left.before_step();
    solver::StepReport r;
    if (!try_step(0.5 * h, r, progress)) {
      restore();  // the state of the step's start, for the retry or the restart point
      retry_smaller(h, ctl_.controller().after_failure(h), failure_, progress);
      return false;
    }
    p_.left.after_step(0.5 * h);
    newton = std::max(newton, r.newton_iterations);
    (part == 0 ? mid : half) = owned_levels(p_.st);
  }
  const double err = ctl_.doubling_error(full, mid, half, h);
  const StepDecision d = ctl_.controller().decide(h, err, newton);
  if (!d.accept) {
    restore();
    ++ctl_.totals().rejected;
    std::ostringstream os;
    os << "the error estimate of the first step (step doubling) is " << err << " times the tolerance";
    retry_smaller(h, d.next_dt, os.str(), progress);
    return false;
  }
  ctl_.accept(std::move(mid), 0.5 * h);
  ctl_.accept(std::move(half), 0.5 * h);
  ctl_.totals().record_accepted(0.5 * h);
  ctl_.totals().record_accepted(0.5 * h);
  ctl_.next_dt = d.next_dt;
  return true;
}

LoopTotals RodAdaptiveLoop::run(bool show_progress) {
  Progress progress(show_progress, "t", "s", p_.st.time(), p_.g.t_end, p_.opt.progress_interval);
  const auto start = std::chrono::steady_clock::now();
  const long outputs = (p_.g.steps + p_.every - 1) / p_.every;
  long k = 1;  // the next output time: the first one after the current time
  // (A restart point at an output time may lie a rounding below it: the landing tolerance.)
  while (k <= outputs && output_time(k) - p_.st.time() <= 1e-9 * p_.g.dt) ++k;
  while (k <= outputs) {
    const double t_out = output_time(k), now = p_.st.time();
    // Land on the output time, and on a node crossing of a moving load before it; a step
    // that would leave less than itself is split in two.
    const double crossing = land_ ? next_node_crossing(loads_, now + 1e-9 * ctl_.next_dt, p_.st.model().ds(),
                                                       p_.st.model().length)
                                  : HUGE_VAL;
    const double target = crossing < t_out - 1e-9 * ctl_.next_dt ? crossing : t_out;
    const double proposed = ctl_.next_dt, h = StepController::landing_step(proposed, target - now);
    const bool accepted = ctl_.has_history() ? extrapolated_step(h, progress) : doubled_step(h, progress);
    if (!accepted) continue;
    ctl_.next_dt = StepController::after_landing(h, proposed, ctl_.next_dt);
    tot_.last_step = ctl_.totals().accepted;
    if (std::abs(t_out - p_.st.time()) <= 1e-9 * h) {
      p_.out.write(p_.w, p_.st.time(), p_.left.position());
      if (p_.rp.due()) p_.rp.store(tot_.last_step, p_.left.position());
      ++k;
    }
    progress.update(p_.st.time(), tot_.last_step, ctl_.next_dt, ctl_.totals());
    if (const int sig = k <= outputs ? interrupt_requested(p_.comm) : 0)
      p_.interrupt(tot_.last_step, "adaptive step " + std::to_string(tot_.last_step), sig, progress);
  }
  progress.done();
  tot_.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return tot_;
}

/// A restart's source file, restart point and state (opt.restart only).
struct RestartSource {
  std::string file;
  output::RestartPoint point;
};
RestartSource read_restart(const scene::Scene& sc, const RunOptions& opt, const TimeGrid& g, rod::RodState& state) {
  RestartSource src;
  const int N = sc.mesh.nodes - 1;
  src.file = output::restart_source(opt.output);
  const std::size_t comps = restart_components(sc);
  const std::size_t other = sc.time.adaptive.enabled ? rod::kPackedNodeValues : rod::kPackedNodeValues + RodAdaptiveControl::kPerNode;
  src.point = read_rod_restart_point(opt.output, src.file, static_cast<std::size_t>(N + 1), comps, other,
                                     sc.time.adaptive.enabled, g.dt, 3);
  state.t = src.point.time;
  state.ds = sc.rod.length / N;
  state.nodes.resize(static_cast<std::size_t>(N + 1));
  for (int j = 0; j <= N; ++j)
    state.nodes[static_cast<std::size_t>(j)] = rod::unpack_node(&src.point.state[comps * static_cast<std::size_t>(j)]);
  return src;
}

/// The adaptive controller of a run: from the restart point when restarting, else started
/// at the current (initial) level.
std::unique_ptr<RodAdaptiveControl> make_adaptive(const scene::Scene& sc, const rod::RodModel& model,
                                                  const solver::RodStepper& st, const RestartSource& restart,
                                                  const TimeGrid& g, MPI_Comm comm) {
  auto ctl = std::make_unique<RodAdaptiveControl>(sc.time.adaptive, g.dt, model.alpha, model.length, comm);
  if (restart.file.empty()) {
    ctl->start(owned_levels(st));
    return ctl;
  }
  const auto& x = restart.point.extra;
  const std::size_t comps = restart_components(sc), first = static_cast<std::size_t>(st.first_owned_node());
  std::vector<double> per_node(RodAdaptiveControl::kPerNode * static_cast<std::size_t>(st.num_owned_nodes()));
  for (std::size_t k = 0; k < static_cast<std::size_t>(st.num_owned_nodes()); ++k)
    for (std::size_t i = 0; i < RodAdaptiveControl::kPerNode; ++i)
      per_node[RodAdaptiveControl::kPerNode * k + i] = restart.point.state[comps * (first + k) + rod::kPackedNodeValues + i];
  ctl->restore(owned_levels(st), per_node, std::vector<double>(x.begin() + std::min<std::size_t>(5, x.size()), x.end()));
  return ctl;
}

// What the stepper would refuse about its linear solver, found before anything is allocated.
void check_linear_solver(const scene::Scene& sc, const RodSetup& setup, MPI_Comm comm) {
  const int ranks = par::size(comm);
  try {
    solver::LinearSolverChoice::resolve(setup.solver, ranks, solver::LinearSolverChoice::Use::time_step);
  } catch (const std::invalid_argument& e) {
    linear_solver_refused(sc, ranks, e);
  }
}

void print_start(const scene::Scene& sc, const TimeGrid& g, const std::string& initial,
                 const solver::RodStepper& st, const std::string& path_text) {
  char steps[160];
  if (sc.time.adaptive.enabled)
    std::snprintf(steps, sizeof steps, "adaptive steps (tolerance %.3g, first dt = %.6g s, outputs every %.6g s)",
                  sc.time.adaptive.tolerance, g.dt, g.dt * sc.output.every);
  else
    std::snprintf(steps, sizeof steps, "%ld steps of dt = %.6g s", g.steps, g.dt);
  std::printf("rod scene '%s': %d nodes, %s to t = %.6g s; initial state: %s; linear solver: %s%s; "
              "path: %s\n",
              sc.file.c_str(), sc.mesh.nodes, steps, g.t_end, initial.c_str(), st.resolved_linear_solver().c_str(),
              st.linear_solver_rerouted() ? " (rerouted: Amesos2 gives wrong answers on 2+ ranks here)" : "",
              path_text.c_str());
}

}  // namespace

void check_rod(const scene::Scene& sc) {
  const RodSetup setup = build_rod_model(sc);
  if (coupled_load(sc)) check_coupled_rod(sc, setup.model);
  precheck_planar(sc, setup.model);
}

void run_rod(const scene::Scene& sc, const RunOptions& opt, MPI_Comm comm) {
  const int rank = par::rank(comm);
  const RodSetup setup = build_rod_model(sc);
  // Kokkos lives from the first rod run of the process to the process's end
  // (finish_solver_runtime), Tpetra for this run only.
  const TpetraScope tpetra(comm);

  // Model, limits and stepper first: the limits (steps, memory, load ratio: run_limits.hpp),
  // the partition (ranks <= nodes), the linear solver and a required planar path are bad
  // input (exit 2), found before anything of the rod's size is allocated and before any
  // initial state is computed.
  const TimeGrid grid = check_rod_run(sc, setup.model, opt.limits, comm).grid;
  check_linear_solver(sc, setup, comm);
  if (coupled_load(sc)) {
    run_rod_coupled(sc, setup, grid, opt, comm);
    return;
  }
  if (!opt.restart) precheck_planar(sc, setup.model);

  // The initial state before the stepper: the static solve's matrices are freed before the
  // stepper allocates its own, so the peak memory is the larger of the two, not their sum.
  InitialState start;
  RestartSource restart;
  if (opt.restart) {
    start.description = "restart";
    restart = read_restart(sc, opt, grid, start.state);
  } else {
    start = initial_state(sc, setup, comm);
  }
  auto stepper = make_stepper(sc, setup, comm);
  stepper->set_state(start.state, start.first_node);

  // Path: the planar fast path or the 3D system (docs/solver.md); a restart keeps the path
  // of the run it continues (restart extra[4]: 1 planar, 0 3D).
  const auto& extra = restart.point.extra;
  const int stored_path = opt.restart && extra.size() >= 5 ? (extra[4] != 0.0 ? 1 : 0) : -1;
  start.state = rod::RodState();  // the stepper holds its own copy
  const PathChoice path = choose_path(sc, setup.model, *stepper, stored_path, comm);
  if (path.planar) stepper->set_planar(&path.symmetry);
  const std::string path_text = stepper->path_description() + "; " + path.detail;

  RodOutputs outputs(sc, setup.model, *stepper, comm);
  if (opt.restart) {
    output::check_restart_outputs(restart.file, outputs.probe_names(), outputs.field_names());
    restart.file = output::move_aside_for_restart(opt.output, comm);
  }
  output::RunInfo info{version_string(), opt.invocation, sc.text, sc.file, "rod", {}};
  info.attributes = {{"rod_path", path.planar ? "planar" : "3D"}, {"rod_path_detail", path_text},
                     {"initial_state", start.description}};
  output::Writer writer(comm, opt.output, opt.overwrite || opt.restart, info, outputs.layout(),
                        std::max<size_t>(1, sc.loads.size()));
  writer.set_intervals(opt.flush_interval, writer.xdmf_interval());
  outputs.declare(writer);

  const Vec3 r0 = opt.restart ? Vec3(extra[0], extra[1], extra[2]) : Vec3(Vec3::Zero());
  LeftEnd left(*stepper, setup.model.left.end_moves(), r0, comm);
  std::unique_ptr<RodAdaptiveControl> adaptive;
  if (sc.time.adaptive.enabled) adaptive = make_adaptive(sc, setup.model, *stepper, restart, grid, comm);
  RodRestartPoints points(*stepper, writer, grid.dt, path.planar, opt.restart_interval, adaptive.get(), comm);
  if (rank == 0 && !opt.quiet) print_start(sc, grid, start.description, *stepper, path_text);
  if (rank == 0 && !adaptive) warn_under_resolved_loads(sc, grid);
  long first_step = 1;
  if (opt.restart) {
    output::copy_output_steps(restart.file, writer, restart.point.steps_written, outputs.probe_names(), outputs.field_names(),
                      static_cast<std::size_t>(stepper->first_owned_node()),
                      static_cast<std::size_t>(stepper->num_owned_nodes()));
    points.store(restart.point.step, left.position());
    output::remove_restart_source(opt.output, comm);
    first_step = restart.point.step + 1;
    if (rank == 0 && !opt.quiet)
      std::printf("restart from %s: time step %ld at t = %.9g s, %zu output steps kept\n", opt.output.c_str(),
                  restart.point.step, restart.point.time, restart.point.steps_written);
  } else {
    outputs.write(writer, 0.0, left.position());
    points.store(0, left.position());
  }
  const bool progress = rank == 0 && progress_wanted(opt.quiet, opt.progress);
  const RodLoopParts parts{*stepper, outputs, writer, points, left, grid, sc.output.every, opt, comm};
  LoopTotals tot;
  if (adaptive) {
    RodAdaptiveLoop loop(parts, *adaptive, sc.loads, sc.time.adaptive.land_on_nodes);
    tot = loop.run(progress);
  } else {
    RodTimeLoop loop(parts, load_ratio(sc));
    tot = loop.run(first_step, progress);
  }
  points.store(tot.last_step, left.position());  // the end (a no-op when the last output step stored it)
  if (adaptive) write_adaptive_totals(writer, adaptive->totals());
  writer.finish();
  if (rank == 0 && !opt.quiet)
    std::printf("done: %ld Newton iterations in %ld solves (%.2f per solve%s) on the %s path; %zu output steps -> %s; "
                "time stepping %.3f s (wall, output included)\n",
                tot.newton, tot.solves, tot.solves ? double(tot.newton) / double(tot.solves) : 0.0,
                retries_note(tot.guess_retries).c_str(), path.planar ? "planar" : "3D", writer.steps_written(),
                opt.output.c_str(), tot.seconds);
  if (rank == 0 && !opt.quiet && adaptive) std::printf("adaptive: %s\n", adaptive->totals().summary().c_str());
}

}  // namespace traverse::app
