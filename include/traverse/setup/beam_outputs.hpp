#pragma once
// What a beam run writes at an output step: the scene's probes, each load's position and the
// deflection under it (moving loads), the coupled mass's probes and energies, each vehicle's
// probes; the fields of beam_fields.hpp. Probe values are kept for a restart's replay check.
#include <mpi.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "traverse/beam/beam_problem.hpp"
#include "traverse/beam/beam_simulation.hpp"
#include "traverse/beam/coupled_mass_beam.hpp"
#include "traverse/beam/mode_set.hpp"
#include "traverse/beam/vehicle_beam.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/setup/beam_fields.hpp"
#include "traverse/setup/step_view.hpp"

namespace traverse::setup {

/// The extremes of a run's probes over every time step (output::ProbeExtremes per probe), for
/// the peaks a summary needs without writing every step.
class ProbeTracker {
 public:
  /// The probes' values at time t, in declaration order.
  void take(double t, const std::vector<std::vector<double>>& probes);
  /// Writes each probe's extremes (nothing before the first take).
  void write(output::Writer& w) const;
  /// Whether the probes at time t were taken last (an output step's, before the step's hook).
  bool taken_at(double t) const { return !e_.empty() && t == last_t_; }
  /// After a time step: the probes of `outputs` at `sim`'s time (outputs.evaluate_probes(sim)),
  /// unless the output step at that time took them already.
  template <class Outputs, class Sim>
  void take_after_step(Outputs& outputs, const Sim& sim) {
    if (taken_at(sim.time())) return;
    outputs.evaluate_probes(sim);
    take(sim.time(), outputs.probes());
  }

 private:
  std::vector<output::ProbeExtremes> e_;
  double last_t_ = 0.0;
};

/// The outputs of a beam run: the probes (deflections, each load's position and the
/// deflection under it) and the fields (the deflection and the deflected shape (x, w, 0)
/// always; slope and bending moment on request) on this rank's contiguous range of nodes (the
/// beam itself is solved, replicated, on every rank: it is a small dense system).
class BeamOutputs {
 public:
  BeamOutputs(const scene::Scene& sc, const beam::BeamProblem& p, const beam::ModeSet& modes, MPI_Comm comm);
  std::vector<std::string> probe_names() const;
  std::vector<std::string> field_names() const;
  const output::NodeLayout& layout() const { return fields_.layout(); }
  void declare(output::Writer& w) const;
  /// Evaluates every output at a snapshot (probe values are kept for the replay check).
  void evaluate(const beam::BeamSnapshot& s);
  /// Evaluates the probes only (probes()).
  void evaluate_probes(const beam::BeamSnapshot& s);
  const std::vector<std::vector<double>>& probes() const { return probes_; }
  void write(output::Writer& w, double t) const;

 private:
  const scene::Scene& sc_;
  BeamFields fields_;
  std::vector<std::vector<double>> probes_;
  std::vector<double> sigma_;
  std::vector<std::size_t> first_;  ///< per scene load: its first load of the problem (a train's head)
};

/// The outputs of a coupled beam run: names, declarations, values at a state.
class CoupledBeamOutputs {
 public:
  CoupledBeamOutputs(const scene::Scene& sc, const scene::MovingLoadSpec& load, const beam::BeamProblem& p,
                     const beam::ModeSet& modes, MPI_Comm comm);
  const output::NodeLayout& layout() const { return fields_.layout(); }
  void declare(output::Writer& w) const;
  std::vector<std::string> probe_names() const;
  std::vector<std::string> field_names() const;
  void evaluate(const beam::CoupledMassBeam& s);
  void evaluate_probes(const beam::CoupledMassBeam& s);
  const std::vector<std::vector<double>>& probes() const { return probes_; }
  void write(output::Writer& w, double t) const {
    w.write_step(t, sigma_, probes_, fields_.views());
  }

 private:
  const scene::Scene& sc_;
  const scene::MovingLoadSpec& load_;
  BeamFields fields_;
  std::vector<std::vector<double>> probes_;
  std::vector<double> sigma_{0.0};
};

/// The outputs of a vehicle run: names, declarations, values at a state.
class VehicleOutputs {
 public:
  VehicleOutputs(const scene::Scene& sc, const beam::BeamProblem& p, const beam::ModeSet& modes, MPI_Comm comm)
      : sc_(sc), fields_(sc, p, modes, comm) {
    for (const auto& l : sc.loads) vehicles_.push_back(&l);
    sigma_.assign(vehicles_.size(), 0.0);
  }
  const output::NodeLayout& layout() const { return fields_.layout(); }
  std::size_t count() const { return vehicles_.size(); }
  std::vector<std::string> probe_names() const;
  std::vector<std::string> field_names() const { return fields_.names(); }
  void declare(output::Writer& w) const;
  void evaluate(const beam::VehicleBeam& s);
  void evaluate_probes(const beam::VehicleBeam& s);
  const std::vector<std::vector<double>>& probes() const { return probes_; }
  void write(output::Writer& w, double t) const { w.write_step(t, sigma_, probes_, fields_.views()); }

 private:
  const scene::Scene& sc_;
  BeamFields fields_;
  std::vector<const scene::MovingLoadSpec*> vehicles_;
  std::vector<std::vector<double>> probes_;
  std::vector<double> sigma_;
};

/// The mode shapes at the output's nodes (those of the field `deflection`), for the deflection
/// a beam's step callback is given.
struct BeamNodeShapes {
  BeamNodeShapes(const scene::Scene& sc, const beam::BeamProblem& p, const beam::ModeSet& modes);
  std::vector<double> x;  ///< the nodes [m]
  std::vector<VecX> phi;  ///< the modes' values at each node
};

/// Calls `cb.beam` on rank 0 with the beam at time step `step` (time t, modal state Y, Y'): the
/// deflection w = Phi Y at the nodes as the field `deflection` evaluates it. Its answer on every
/// rank (each rank solves the whole beam: no gathering). Collective.
bool call_beam_back(const StepCallback& cb, long step, double t, const VecX& Y, const VecX& Ydot,
                    const BeamNodeShapes& shapes, MPI_Comm comm);

/// The function a beam run's time::StepHookObserver calls after a time step: call_beam_back with
/// the state of `sim` (a BeamSimulation, a CoupledMassBeam or a VehicleBeam: time(), Y(), Ydot(),
/// modes()). The shapes are evaluated only when `cb` has a beam callback; `cb` and `sim` must
/// outlive the function.
template <class Sim>
std::function<bool(long)> beam_step_hook(const StepCallback& cb, const Sim& sim, const scene::Scene& sc,
                                         const beam::BeamProblem& p, MPI_Comm comm) {
  if (!cb.beam) return [](long) { return true; };
  auto shapes = std::make_shared<const BeamNodeShapes>(sc, p, sim.modes());
  return [&cb, &sim, shapes, comm](long step) {
    return call_beam_back(cb, step, sim.time(), sim.Y(), sim.Ydot(), *shapes, comm);
  };
}

}  // namespace traverse::setup
