#pragma once
// Scene -> rod structures shared by the dynamic and the static runners.
#include <mpi.h>

#include <Teuchos_ParameterList.hpp>

#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "traverse/output/continuation_writer.hpp"
#include "traverse/rod/end_condition.hpp"
#include "traverse/rod/planar.hpp"
#include "traverse/rod/rod_model.hpp"
#include "traverse/rod/static_kernels.hpp"
#include "traverse/rod/static_problem.hpp"
#include "traverse/rod/static_load_steps.hpp"
#include "traverse/rod/rod_state.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/solver/rod_stepper.hpp"
#include "traverse/solver/step_failure.hpp"
#include "traverse/setup/run_limits.hpp"

namespace traverse::setup {

/// The rod module's word for rod.model.
rod::RodStrain rod_strain(scene::RodStrain s);
/// Section and material of the scene's rod (with rod.model's compliance and rod.damping).
rod::RodProperties rod_properties(const scene::RodSpec& r);

/// What an arch start (initial_state: arch) depends on in the scene: the rod, the mesh,
/// initial_state.end_to_end and gravity, as text; a process keeps its last arch under it (and,
/// for LOCA's formation, the solver parameters and the rank count) for the next case of a sweep.
std::string arch_scene_key(const scene::Scene& sc);

/// The dynamic start at rest from a formed arch (`problem`, `state`: the arch under gravity).
/// With initial_state.loaded it is first solved again with the scene's one load at t = 0 on it
/// (`solve`: Newton on that problem from the arch's state, in one process or over the ranks),
/// what that took appended to `description`; a failure throws std::runtime_error.
rod::RodState arch_dynamic_start(
    const scene::Scene& sc, const rod::StaticProblem& problem, const std::vector<rod::StaticNode>& state,
    const std::function<rod::StaticReport(const rod::StaticProblem&, std::vector<rod::StaticNode>&)>& solve,
    std::string& description);

/// Stage 1 of a rod run: the rod model of a scene (material, scheme, ends, loads) and its
/// validated solver parameters. Throws SceneError (solver parameters, a pair of end
/// conditions that is not well posed).
struct RodSetup {
  rod::RodModel model;
  Teuchos::ParameterList solver;
};
RodSetup build_rod_model(const scene::Scene& sc);

/// Stage 2: the initial state of a dynamic run (initial_state: static, rest, arch or file)
/// and a sentence saying what it is. The static equilibrium and the rest state are computed
/// as pieces, each rank holding its nodes and their ghosts only (as DistributedStepper
/// partitions the rod: first_ghosted_node, num_ghosted_nodes); the arch and a state file give
/// all N + 1 nodes on every rank (first_node 0). Throws NumericsError when the static solve
/// or the arch formation fails, SceneError for a bad state file.
struct InitialState {
  rod::RodState state;
  int first_node = 0;  ///< global index of state.nodes.front()
  std::string description;
};
InitialState initial_state(const scene::Scene& sc, const RodSetup& setup, MPI_Comm comm);

/// The dynamic end condition of a scene end.
rod::EndCondition rod_end(const scene::EndSpec& e);

/// The static reading of a scene end placed at the straight reference position (0, 0, s_end).
rod::StaticEnd static_end(const scene::EndSpec& e, double s_end);

/// Static state <-> the node arrays of a continuation file.
output::NodalState nodal_state(const std::vector<rod::StaticNode>& nodes);
/// The static nodes (theta = 0) of a saved state; throws SceneError (located at `key`) when
/// its node count differs from the scene's.
std::vector<rod::StaticNode> static_nodes(const output::NodalState& st, const scene::Scene& sc, const std::string& key);

/// The static problem of a rod scene with its continuation parameters at the scene's
/// values (the single load's start and force, gravity factor 1, the right end's given force
/// and position).
rod::StaticProblem static_problem(const scene::Scene& sc);

/// initial_state: file: the state saved by a continuation run, at rest (every node on every
/// rank); `description` says which. Throws SceneError (located at initial_state.file) for a
/// bad file.
rod::RodState file_start(const scene::Scene& sc, std::string& description);

/// The fixed-frame vector of each point force of the scene's rod model, in model order (the
/// loads without inertia; a moving mass's weight comes from gravity).
std::vector<Vec3> point_force_vectors(const scene::Scene& sc);

/// Which system a dynamic rod run solves (scheme.planar, docs/solver.md "Planar fast path").
struct PathChoice {
  bool planar = false;
  rod::PlanarSymmetry symmetry;  ///< when planar
  std::string detail;            ///< how it was chosen, or why the scene is not planar
};

/// rod::check_planar of the scene's model (loads, gravity, end conditions, intrinsic
/// curvature) in the straight reference state along k, on a 2-cell copy of the model
/// (planarity does not depend on the mesh; nothing of the rod's size is allocated).
rod::PlanarCheck reference_state_planarity(const scene::Scene& sc, const rod::RodModel& model);

/// scheme.planar: on, checked before any initial state is computed: the model (loads,
/// gravity, end conditions, intrinsic curvature) against the straight reference state along
/// k. Throws SceneError located at scheme.planar when it cannot be planar.
void precheck_planar(const scene::Scene& sc, const rod::RodModel& model);

/// The path for a run starting from the stepper's state: scheme.planar off -> 3D; on ->
/// planar or SceneError at scheme.planar; auto -> planar when rod::check_planar says so (each
/// rank sums up its own nodes: rod::summarize_planarity). `stored` is the path of the run
/// being restarted (-1 none or unknown, 0 3D, 1 planar): with auto a restart keeps it (a
/// stored planar path whose state is no longer planar throws SceneError). Collective.
PathChoice choose_path(const scene::Scene& sc, const rod::RodModel& model, const solver::RodStepper& stepper,
                       int stored, MPI_Comm comm);

/// SceneError located at `solver`: the scene's linear solver cannot run on `ranks` ranks.
[[noreturn]] void linear_solver_refused(const scene::Scene& sc, int ranks, const std::invalid_argument& e);

/// The global nodes `wanted` of the stepper's distributed state, on every rank (collective:
/// each rank packs the ones it owns, one sum-reduction of wanted.size() nodes).
std::vector<rod::RodNode> gather_nodes(const solver::RodStepper& st, const std::vector<int>& wanted, MPI_Comm comm);

/// The time stepper of a scene's rod model (collective); a linear solver that cannot run on
/// this many ranks is bad input (linear_solver_refused).
std::unique_ptr<solver::RodStepper> make_stepper(const scene::Scene& sc, const RodSetup& setup, MPI_Comm comm);

/// The message of a failed fixed step: where and why, and what to try. A step far shorter
/// than the time a bending wave needs to cross a cell cannot converge by shortening it: the
/// residual's 1/dt terms round above the absolute residual tolerance.
std::string explain_step_failure(const std::string& where, const solver::StepFailure& e, const rod::RodModel& model,
                                 const TimeGrid& g, const LoadRatio& load);

}  // namespace traverse::setup
