// The compiled part of the Python package traverse (traverse._traverse): reading, checking
// and running scenes in the calling process, through the same functions as the executable
// (scene::load_scene / parse_scene with the --set strings, the checks of `traverse check`,
// app::run_scene). The Python side (src/python/traverse/) keeps a scene as its source and its
// overrides and calls these functions with them, so that every message is the program's.
#include <mpi.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <filesystem>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "interrupt.hpp"
#include "run.hpp"
#include "traverse/core/numerics_error.hpp"
#include "traverse/output/output_error.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/setup/run_checks.hpp"
#include "traverse/setup/solver_access.hpp"
#include "traverse/version.hpp"

namespace py = pybind11;
using namespace traverse;

namespace {

// Where a scene comes from: a file (`path`, read by load_scene) or YAML text (`text`, named
// `name` in messages), with the --set strings applied in order.
struct Source {
  bool is_file = true;
  std::string path_or_text;
  std::string name;
  std::vector<std::string> overrides;
};

scene::Scene load(const Source& s) {
  return s.is_file ? scene::load_scene(s.path_or_text, s.overrides)
                   : scene::parse_scene(s.path_or_text, s.name, s.overrides);
}

// Raises the exception class `name` of traverse._errors with `message`; `output`, when not
// empty, becomes its attribute `output` (the file a failed run left).
[[noreturn]] void raise(const char* name, const std::string& message, const std::string& output = {}) {
  py::gil_scoped_acquire gil;
  py::object cls = py::module_::import("traverse._errors").attr(name);
  py::object err = cls(message);
  if (!output.empty()) err.attr("output") = output;
  PyErr_SetObject(cls.ptr(), err.ptr());
  throw py::error_already_set();
}

// Calls `f`, turning the program's exceptions into the package's: the messages are the ones
// the command line prints after "traverse: bad scene: " and the like.
template <class F>
auto translated(F&& f, const std::string& output = {}) -> decltype(f()) {
  try {
    return f();
  } catch (const py::error_already_set&) {
    throw;
  } catch (const scene::SceneError& e) {
    raise("SceneError", e.what());
  } catch (const output::OutputError& e) {
    raise("OutputError", e.what());
  } catch (const output::RestartError& e) {
    raise("OutputError", e.what());
  } catch (const app::UsageError& e) {
    raise("SceneError", e.message);
  } catch (const NumericsError& e) {
    // A failed time step leaves the steps written so far; a failed start writes nothing.
    raise("RunError", e.what(), !output.empty() && std::filesystem::exists(output) ? output : std::string());
  } catch (const app::Interrupted& e) {
    raise("RunError", e.what(), e.output());
  }
}

// MPI as this module found or started it. Started here only when nobody had (an Open MPI
// singleton outside mpirun), and then finalised by finish() at the interpreter's exit.
struct MpiState {
  bool started_here = false;
  bool finished = false;
};
MpiState& mpi_state() {
  static MpiState s;
  return s;
}

void ensure_mpi() {
  int initialized = 0, finalized = 0;
  MPI_Initialized(&initialized);
  MPI_Finalized(&finalized);
  if (finalized) throw std::runtime_error("traverse: MPI was already finalised in this process; no run can start");
  if (initialized) return;
  // Serialized: calls take a lock (run_mutex), so that one thread at a time calls MPI.
  int provided = 0;
  MPI_Init_thread(nullptr, nullptr, MPI_THREAD_SERIALIZED, &provided);
  mpi_state().started_here = true;
}

// One call into the program at a time (a run, a check or a read of a scene): the program is
// not written for concurrent runs in one process. Taken with the interpreter's lock released.
std::mutex& run_mutex() {
  static std::mutex m;
  return m;
}

// Ends what runs started for the process, in the executable's order (main.cpp): Kokkos
// (kept alive from the first rod run to the last, setup::finish_solver_runtime), then MPI if
// this module started it. Registered with atexit by the package; harmless when called again.
void finish() {
  py::gil_scoped_release nogil;  // a run in another thread may need it to raise its error
  std::lock_guard<std::mutex> lock(run_mutex());
  setup::finish_solver_runtime();
  MpiState& s = mpi_state();
  if (s.started_here && !s.finished) {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized) MPI_Finalize();
    s.finished = true;
  }
}

// What `traverse check` prints for the scene: the plan and the complete scene (YAML, every
// default filled in, with or without its comments). Runs the same checks, in this process
// alone as the command does outside a launcher.
std::pair<std::string, std::string> check(const Source& s, bool comments) {
  py::gil_scoped_release nogil;
  std::lock_guard<std::mutex> lock(run_mutex());
  return translated([&] {
    const scene::Scene sc = load(s);
    if (sc.model == scene::Model::Rod) app::check_rod(sc);
    const std::string plan = setup::check_run(sc, setup::RunLimits{}, MPI_COMM_NULL);
    return std::make_pair(plan, scene::describe_scene(sc, comments));
  });
}

// Reads the scene only (what --set is checked against before anything runs).
void validate(const Source& s) {
  py::gil_scoped_release nogil;
  std::lock_guard<std::mutex> lock(run_mutex());
  translated([&] { (void)load(s); });
}

// Runs the scene into `output` as `traverse run SCENE -o OUTPUT [--overwrite] [-q]` does, on
// MPI_COMM_WORLD (every rank of an MPI launch calls it). The GIL is released while it runs.
void run(const Source& s, const std::string& output, bool overwrite, bool quiet, bool verbose,
         const std::string& invocation) {
  py::gil_scoped_release nogil;
  std::lock_guard<std::mutex> lock(run_mutex());
  if (mpi_state().finished) throw std::runtime_error("traverse: the module was shut down (interpreter exit)");
  translated(
      [&] {
        ensure_mpi();
        const scene::Scene sc = load(s);
        app::RunOptions opt;
        opt.output = output;
        opt.restart_interval = sc.output.restart_interval;
        opt.overwrite = overwrite;
        opt.quiet = quiet;
        opt.verbose = verbose && !quiet;
        opt.invocation = invocation;
        app::run_scene(sc, opt, MPI_COMM_WORLD);
      },
      output);
}

}  // namespace

PYBIND11_MODULE(_traverse, m) {
  m.doc() = "traverse's compiled core: scenes read, checked and run in this process (use the package traverse)";
  py::class_<Source>(m, "Source")
      .def(py::init([](bool is_file, std::string path_or_text, std::string name, std::vector<std::string> overrides) {
             return Source{is_file, std::move(path_or_text), std::move(name), std::move(overrides)};
           }),
           py::arg("is_file"), py::arg("path_or_text"), py::arg("name"), py::arg("overrides"));
  m.def("check", &check, py::arg("source"), py::arg("comments") = true,
        "(plan, complete scene as YAML) as `traverse check` prints them; raises SceneError");
  m.def("validate", &validate, py::arg("source"), "reads the scene with its overrides; raises SceneError");
  m.def("run", &run, py::arg("source"), py::arg("output"), py::arg("overwrite") = false, py::arg("quiet") = true,
        py::arg("verbose") = false, py::arg("invocation") = "",
        "runs the scene into the HDF5 file `output` (app::run_scene); raises SceneError, OutputError, RunError");
  m.def("finish", &finish, "ends Kokkos and, when this module started it, MPI (at the interpreter's exit)");
  m.def("mpi_started_here", [] { return mpi_state().started_here; }, "whether this module called MPI_Init_thread");
  m.attr("version") = version_string();
}
