// traverse: parse the command line, read the scene, dispatch, report.
#include <mpi.h>

#include <iostream>
#include <string>

#include "cli.hpp"
#include "interrupt.hpp"
#include "mpi_session.hpp"
#include "restart.hpp"
#include "run.hpp"
#include "traverse/setup/solver_access.hpp"
#include "sweep.hpp"
#include "traverse/output/output_error.hpp"
#include "traverse/output/sidecar.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/version.hpp"

using namespace traverse;

namespace {

// Whether `command` starts MPI: a run and a sweep always; check and xdmf under an MPI launcher
// (where every rank takes part); --help and --version never.
bool needs_mpi(app::CommandLine::Command command, const app::Launch& launch) {
  using Command = app::CommandLine::Command;
  switch (command) {
    case Command::Help:
    case Command::Version: return false;
    case Command::Check:
    case Command::Xdmf: return launch.by_launcher;
    case Command::Run:
    case Command::Sweep: return true;
    default: throw std::logic_error("traverse: command not handled");
  }
}

// `comm`: MPI_COMM_WORLD, or MPI_COMM_NULL when the command runs without MPI (needs_mpi).
int execute(const app::CommandLine& cl, int rank, MPI_Comm comm) {
  using Command = app::CommandLine::Command;
  switch (cl.command) {
    case Command::Help:
      if (rank == 0) std::cout << app::usage_text();
      return app::kSuccess;
    case Command::Version:
      if (rank == 0) std::cout << "traverse " << version_string() << "\n";
      return app::kSuccess;
    case Command::Check: {
      const scene::Scene sc = scene::load_scene(cl.scene, cl.overrides);
      if (sc.model == scene::Model::Rod) app::check_rod(sc);
      const std::string plan = setup::check_run(sc, cl.limits, comm);
      if (rank == 0) {
        for (const std::string& w : setup::adaptive_warnings(sc))
          std::fprintf(stderr, "traverse: warning: %s\n", w.c_str());
        std::cout << "# " << cl.scene << ": valid (" << plan << "). The complete scene, every default filled in:\n"
                  << scene::describe_scene(sc);
        if (cl.types) std::cout << "\n" << scene::describe_types();
      }
      return app::kSuccess;
    }
    case Command::Xdmf: {  // rank 0 works; every rank returns its outcome
      std::string error;
      if (rank == 0) {
        try {
          const auto r = output::write_sidecar(cl.scene, cl.output);
          std::cout << "traverse xdmf: wrote " << r.xmf_path << " (" << r.steps << " output steps"
                    << (r.views_created ? ", " + std::to_string(r.views_created) + " views added to " + cl.scene : "")
                    << ")\n";
        } catch (const output::OutputError& e) {
          error = e.what();
        }
      }
      int failed = error.empty() ? 0 : 1;
      if (comm != MPI_COMM_NULL) MPI_Bcast(&failed, 1, MPI_INT, 0, comm);
      if (failed) throw app::UsageError{"xdmf " + cl.scene + ": " + (rank == 0 ? error : std::string("failed"))};
      return app::kSuccess;
    }
    case Command::Run: {
      app::install_interrupt_handlers();
      const bool restart = !cl.restart.empty();
      const scene::Scene sc = restart ? app::restart_scene(cl.restart, cl.scene, cl.overrides)
                                      : scene::load_scene(cl.scene, cl.overrides);
      if (restart && sc.model == scene::Model::Rod && sc.continuation.enabled)
        throw app::UsageError{"--restart " + cl.restart + ": continuation (statics) runs cannot be restarted"};
      app::RunOptions opt;
      opt.output = restart ? cl.restart : cl.output.empty() ? sc.output.file : cl.output;
      opt.restart = restart;
      opt.restart_interval = cl.restart_interval >= 0.0 ? cl.restart_interval : sc.output.restart_interval;
      opt.overwrite = cl.overwrite;
      opt.quiet = cl.quiet;
      opt.verbose = cl.verbose && !cl.quiet;
      opt.progress = cl.progress;
      opt.invocation = cl.invocation;
      opt.limits = cl.limits;
      app::run_scene(sc, opt, comm);
      return app::kSuccess;
    }
    case Command::Sweep:
      app::install_interrupt_handlers();
      return app::run_sweep(cl, app::plan_sweep(cl), comm);
    default:
      throw std::logic_error("traverse: command not handled");
  }
}

}  // namespace

int main(int argc, char** argv) {
  // MPI only for the commands that need it (needs_mpi); until it starts, the rank is the
  // launcher's (0 outside one), so that one rank reports.
  const app::Launch launch = app::launch_from_environment();
  app::MpiSession mpi;
  int rank = launch.rank;
  int code = app::kSuccess;
  auto report = [&](const std::string& kind, const std::string& msg) {
    if (rank == 0) std::cerr << "traverse: " << kind << msg << "\n";
  };
  try {
    const app::CommandLine cl = app::parse_command_line(argc, argv);
    if (needs_mpi(cl.command, launch)) {
      mpi.start(&argc, &argv);
      rank = mpi.rank();
    }
    code = execute(cl, rank, mpi.comm());
  } catch (const app::UsageError& e) {
    report("", e.message + "\n(see traverse --help)");
    code = app::kBadInput;
  } catch (const output::RestartError& e) {
    report("", std::string(e.what()) + "\n(see traverse --help)");
    code = app::kBadInput;
  } catch (const scene::SceneError& e) {
    report("bad scene: ", e.what());
    code = app::kBadInput;
  } catch (const output::OutputError& e) {
    report("bad output path: ", e.what());
    code = app::kBadInput;
  } catch (const app::Interrupted& e) {
    // Every rank stopped at the same step; the writer is closed: set the final status.
    output::set_file_status(e.output(), e.status(), mpi.comm());
    report("", e.what());
    code = 128 + e.signal();
  } catch (const NumericsError& e) {
    report("numerics failed: ", e.what());
    code = app::kNumericsFailed;
  } catch (const std::exception& e) {
    report("error: ", e.what());
    code = app::kOtherError;
  }
  setup::finish_solver_runtime();
  mpi.finish();
  return code;
}
