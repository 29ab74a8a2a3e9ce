// traverse: parse the command line, read the scene, dispatch, report.
#include <mpi.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <string>

#include "cli.hpp"
#include "hand_over.hpp"
#include "heap_pages.hpp"
#include "interrupt.hpp"
#include "mpi_session.hpp"
#include "restart.hpp"
#include "run.hpp"
#include "sweep.hpp"
#include "trilinos_parts.hpp"
#include "traverse/output/output_error.hpp"
#include "traverse/output/sidecar.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/version.hpp"

using namespace traverse;

namespace {

// Whether `command` needs MPI: check and xdmf only under an MPI launcher (where every rank
// takes part); --help and --version never; a run or a sweep in traverse-trilinos always, in
// traverse only under a launcher (traverse hands runs under a launcher to traverse-trilinos;
// what it runs itself in one process runs on MPI_COMM_NULL, without starting MPI; a sweep under
// a launcher spreads its cases over the ranks).
bool needs_mpi(app::CommandLine::Command command, const app::Launch& launch) {
  using Command = app::CommandLine::Command;
  switch (command) {
    case Command::Help:
    case Command::Version: return false;
    case Command::Check:
    case Command::Xdmf: return launch.by_launcher;
    case Command::Run:
    case Command::Sweep: return app::has_trilinos() || launch.by_launcher;  // traverse: this process alone
    default: throw std::logic_error("traverse: command not handled");
  }
}

// `comm`: MPI_COMM_WORLD, or MPI_COMM_NULL when the command runs without MPI (needs_mpi).
// `prepared`: what needs_trilinos loaded (traverse), used instead of loading it again.
int execute(const app::CommandLine& cl, int rank, MPI_Comm comm, app::Prepared& prepared) {
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
      const std::string plan = app::check_run(sc, cl.limits, comm);
      if (rank == 0) {
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
      const scene::Scene sc = prepared.scene                ? std::move(*prepared.scene)
                              : restart ? app::restart_scene(cl.restart, cl.scene, cl.overrides)
                                        : scene::load_scene(cl.scene, cl.overrides);
      if (restart && sc.model == scene::Model::Rod && sc.continuation.enabled)
        throw app::UsageError{"--restart " + cl.restart + ": continuation (statics) runs cannot be restarted"};
      app::RunOptions opt;
      opt.output = restart ? cl.restart : cl.output.empty() ? sc.output.file : cl.output;
      opt.restart = restart;
      opt.restart_interval = cl.restart_interval >= 0.0 ? cl.restart_interval : sc.output.restart_interval;
      opt.overwrite = cl.overwrite;
      opt.quiet = cl.quiet;
      opt.progress = cl.progress;
      opt.invocation = cl.invocation;
      opt.limits = cl.limits;
      app::run_scene(sc, opt, comm);
      return app::kSuccess;
    }
    case Command::Sweep:
      app::install_interrupt_handlers();
      return app::run_sweep(cl, prepared.sweep ? *prepared.sweep : app::plan_sweep(cl), comm);
    default:
      throw std::logic_error("traverse: command not handled");
  }
}

// traverse sweep -j J: worker processes forked before MPI starts (never under a launcher);
// each starts MPI itself when its cases need it (needs_mpi).
int sweep_in_workers(const app::CommandLine& cl, const app::Launch& launch, app::Prepared& prepared, app::MpiSession& mpi,
                     int* argc, char*** argv) {
  if (launch.by_launcher)
    throw app::UsageError{"--jobs " + std::to_string(cl.jobs) +
                          ": expected without an MPI launcher (under mpirun the cases spread over its ranks: "
                          "mpirun -n K traverse sweep ... without --jobs)"};
  app::install_interrupt_handlers();
  return app::run_sweep_jobs(cl, prepared.sweep ? *prepared.sweep : app::plan_sweep(cl), [&] {
    if (needs_mpi(cl.command, launch)) mpi.start(argc, argv, launch, true);
    return mpi.comm();
  });
}

}  // namespace

int main(int argc, char** argv) {
  // Memory once touched stays with the process and is reused (no mmap per large block, no
  // trimming of the heap's top), and the heap's first 8 MiB lie on 2 MiB pages, one page fault
  // each: a first touch of a 4 KiB page is the costliest thing a small run does on some virtual
  // machines (about 10 us here; heap_pages.hpp). TRAVERSE_HUGE_PAGES=0: 4 KiB pages.
  const char* huge = std::getenv("TRAVERSE_HUGE_PAGES");
  app::set_up_heap(huge && std::string(huge) == "0" ? 0 : std::size_t{8} << 20);
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
    app::Prepared prepared;
    if (!app::has_trilinos() && app::needs_trilinos(cl, launch, prepared)) app::hand_over_to_trilinos(argv);
    if (cl.command == app::CommandLine::Command::Sweep && cl.jobs > 1) {
      code = sweep_in_workers(cl, launch, prepared, mpi, &argc, &argv);
    } else {
      if (needs_mpi(cl.command, launch)) {
        mpi.start(&argc, &argv, launch, cl.command == app::CommandLine::Command::Sweep);
        rank = mpi.rank();
      }
      code = execute(cl, rank, mpi.comm(), prepared);
    }
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
  } catch (const app::NumericsError& e) {
    report("numerics failed: ", e.what());
    code = app::kNumericsFailed;
  } catch (const std::exception& e) {
    report("error: ", e.what());
    code = app::kOtherError;
  }
  app::finish_solver_runtime();
  mpi.finish();
  return code;
}
