#pragma once
// What a rod run writes at an output step: the scene's probes and fields (the quantity table
// of rod_quantities.hpp), each load's position, and for a coupled mass its probes and the
// energies.
#include <mpi.h>

#include <string>
#include <vector>

#include "traverse/core/types.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/rod/coupled_mass_rod.hpp"
#include "traverse/rod/rod_model.hpp"
#include "traverse/rod/rod_state.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/solver/coupled_rod_time_model.hpp"
#include "traverse/solver/rod_stepper.hpp"
#include "traverse/setup/step_view.hpp"

namespace traverse::setup {

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
  /// Calls `cb` on rank 0 with the whole rod after time step `step` at time t (r0: the left
  /// end's position); its answer on every rank. Collective.
  bool call_back(const StepCallback& cb, long step, double t, const Vec3& r0) const;

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

/// The mass that rides on the rod by itself (a coupled_mass) or on its own suspension at the
/// prescribed path (a sprung_mass: the wheel's mass, the body on its spring and damper along j).
rod::CoupledRodMass coupled_rod_mass(const scene::MovingLoadSpec& load);

/// The step callback of a coupled-mass run: the whole rod `s` and its centreline `r` (held
/// whole on every rank) and the mass `m` (with its body when `suspended`); `cb.rod` is called
/// on rank 0 and its answer holds on every rank of `comm`.
bool coupled_call_back(const StepCallback& cb, long step, const rod::RodState& s, const std::vector<Vec3>& r,
                       const rod::CoupledMassState& m, bool suspended, MPI_Comm comm);

/// The outputs of a rod run with a coupled or sprung mass: the scene's probes and fields, the
/// mass's probes (position, speed, fixed-frame position and velocity, contact forces; for a
/// sprung mass the body's displacement and acceleration and the contact force along d2) and the
/// energies, from the whole state (kept on every rank); the fields of this rank's nodes.
class CoupledRodOutputs {
 public:
  /// `mass`: the stepper's (coupled_rod_mass of `load`); the fields of nodes first .. first +
  /// count - 1 are this rank's.
  CoupledRodOutputs(const scene::Scene& sc, const scene::MovingLoadSpec& load, const rod::CoupledRodMass& mass,
                    const rod::RodModel& model, int first, int count)
      : sc_(sc), load_(load), mass_(mass), model_(model), first_(first), count_(count) {}
  output::NodeLayout layout() const {
    output::NodeLayout l;
    l.global_count = static_cast<size_t>(sc_.mesh.nodes);
    l.first = static_cast<size_t>(first_);
    l.count = static_cast<size_t>(count_);
    for (int j = first_; j < first_ + count_; ++j) l.s.push_back(j * sc_.mesh.ds);
    return l;
  }
  void declare(output::Writer& w) const;
  std::vector<std::string> probe_names() const;
  std::vector<std::string> field_names() const;
  /// Evaluates the outputs at a state and writes them.
  void write(output::Writer& w, const rod::RodState& s, const std::vector<Vec3>& r, const rod::CoupledMassState& m,
             const solver::ContactHistory& c);

 private:
  const scene::Scene& sc_;
  const scene::MovingLoadSpec& load_;
  const rod::CoupledRodMass& mass_;
  const rod::RodModel& model_;
  int first_, count_;
  std::vector<std::vector<double>> probes_, fields_;
};

}  // namespace traverse::setup
