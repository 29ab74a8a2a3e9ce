#pragma once
// The executable traverse links no Trilinos solver library (trilinos_parts.hpp). A command
// that needs one is handed over, before anything starts, to traverse-trilinos (the same
// program with the Trilinos parts) in the same directory: the process image is replaced
// (execv: the same pid, arguments, environment and standard streams), so the user sees one
// run (docs/developer.md, "Start-up").
#include <optional>
#include <string>

#include "cli.hpp"
#include "mpi_session.hpp"
#include "sweep.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::app {

/// What a command loads before anything starts, kept for it: a run's scene (or a restart's),
/// a sweep's plan. Loaded once: traverse decides its hand-over with them, and the command uses
/// them.
struct Prepared {
  std::optional<scene::Scene> scene;  ///< run (not under a launcher): the scene it runs
  std::optional<SweepPlan> sweep;     ///< sweep: its checked cases
};

/// What needs Trilinos: any run under an MPI launcher; a run of a rod scene with a
/// continuation section, an arch initial state, or a solver section that asks for more than
/// the block-tridiagonal LU with BlockNewton (rod_setup: needs_tpetra); a sweep with such a
/// case (each case runs on one rank). --help, --version, check, xdmf and the beam never do.
/// Loads the run's scene, or plans the sweep's cases, into `prepared` (as the command would:
/// a bad scene or sweep throws here as it would there).
bool needs_trilinos(const CommandLine& cl, const Launch& launch, Prepared& prepared);

/// Whether a run of `sc` in one process needs Trilinos (a continuation, or a rod run that does
/// not step on block storage: rod_setup's needs_tpetra). Throws SceneError for a bad model.
bool scene_needs_trilinos(const scene::Scene& sc);

/// Replaces this process by traverse-trilinos with the same arguments; returns only by
/// throwing std::runtime_error (naming the executable) when that cannot start.
[[noreturn]] void hand_over_to_trilinos(char** argv);

}  // namespace traverse::app
