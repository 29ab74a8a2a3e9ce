#pragma once
// The arch formation of a scene (initial_state: arch), for the Trilinos parts only
// (solver_access.cpp and run_statics.cpp).
#include <Teuchos_Comm.hpp>
#include <Teuchos_ParameterList.hpp>
#include <Teuchos_RCP.hpp>

#include <string>

#include "traverse/scene/scene.hpp"
#include "traverse/solver/arch_formation.hpp"

namespace traverse::setup {

/// The scene's rod formed into an arch with end-to-end distance initial_state.end_to_end
/// (solver::form_arch); throws std::runtime_error saying which stage failed.
solver::ArchFormation form_arch(const scene::Scene& sc, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                const Teuchos::ParameterList& solver);
/// One line describing a formed arch, for the log.
std::string arch_summary(const solver::ArchFormation& arch);

}  // namespace traverse::setup
