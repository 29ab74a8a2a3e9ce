#pragma once
// From a rod scene with a `continuation` section to the static problem, its start and the
// continuation's options (the solver module's solver::continue_ and switch_branch).
#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

#include <string>
#include <vector>

#include "traverse/rod/static_problem.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/solver/static_continuation.hpp"

namespace traverse::setup {

/// A scalar probe of a static state from its scene declaration (rod_quantities.hpp).
rod::StaticProbe make_probe(const scene::ContinuationProbeSpec& p);

/// The solver's parameter of a scene's continuation parameter.
rod::StaticParameter static_parameter(scene::ContinuationParameter p);

/// The scene's solver parameters, validated (SceneError at `solver`) and handed on as given,
/// so that the statics' own default for 2+ ranks applies when the scene names no
/// preconditioner.
Teuchos::ParameterList statics_solver_parameters(const scene::Scene& sc);

/// The starting state of the continuation from the scene's initial state (straight, a
/// continuation file, or the formed arch: then `problem` takes the arch's ends and position
/// with the scene's load on top, and `description` says how the arch was formed). Throws
/// NumericsError when the arch formation fails, SceneError for a bad state file.
std::vector<rod::StaticNode> statics_start(const scene::Scene& sc, const Teuchos::ParameterList& solver_params,
                                           const Teuchos::RCP<const Teuchos::Comm<int>>& tcomm,
                                           rod::StaticProblem& problem, std::string& description);

/// The continuation's options from the scene's continuation section, from `start` to its stop.
solver::ContinuationOptions continuation_options(const scene::ContinuationSpec& cs, rod::StaticParameter par,
                                                 double start, const Teuchos::ParameterList& solver_params);

}  // namespace traverse::setup
