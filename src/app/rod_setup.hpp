#pragma once
// Scene -> rod structures shared by the dynamic and the static runners.
#include "traverse/output/continuation_writer.hpp"
#include "traverse/rod/end_condition.hpp"
#include "traverse/rod/static_kernels.hpp"
#include "traverse/rod/static_problem.hpp"
#include "traverse/rod/rod_state.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/solver/arch_formation.hpp"

namespace traverse::app {

/// Section and material of the scene's rod.
rod::RodProperties rod_properties(const scene::RodSpec& r);

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

/// The scene's rod formed into an arch with end-to-end distance initial_state.end_to_end
/// (solver::form_arch); throws std::runtime_error saying which stage failed.
solver::ArchFormation form_arch(const scene::Scene& sc, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                const Teuchos::ParameterList& solver);
/// One line describing a formed arch, for the log.
std::string arch_summary(const solver::ArchFormation& arch);

/// The dynamic initial state of a rod scene whose initial_state is `arch` (formed here) or
/// `file` (a state saved by a continuation run); `description` says what was done. Throws
/// SceneError for a bad file and std::runtime_error when forming fails.
rod::RodState static_start(const scene::Scene& sc, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                           const Teuchos::ParameterList& solver, std::string& description);

}  // namespace traverse::app
