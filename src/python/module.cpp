// The compiled part of the Python package traverse (traverse._traverse): reading, checking
// and running scenes in the calling process, through the same functions as the executable
// (scene::load_scene / parse_scene with the --set strings, the checks of `traverse check`,
// app::run_scene). The Python side (src/python/traverse/) keeps a scene as its source and its
// overrides and calls these functions with them, so that every message is the program's.
#include <mpi.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <string>
#include <utility>
#include <vector>

#include "interrupt.hpp"
#include "restart.hpp"
#include "run.hpp"
#include "run_beam_coupled.hpp"
#include "sweep.hpp"
#include "traverse/core/numerics_error.hpp"
#include "traverse/output/output_error.hpp"
#include "traverse/output/reader.hpp"
#include "traverse/output/restart.hpp"
#include "traverse/scene/scene.hpp"
#include "traverse/setup/run_checks.hpp"
#include "traverse/setup/solver_access.hpp"
#include "traverse/setup/step_view.hpp"
#include "traverse/time/time_integrator.hpp"
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
    // Every rank stopped at the same step and the writer is closed: the final status, as main.cpp sets it.
    output::set_file_status(e.output(), e.status(), MPI_COMM_WORLD);
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

// A read-only numpy array of `data` (copied) in the shape `shape`.
py::array_t<double> frozen(const std::vector<double>& data, std::vector<py::ssize_t> shape) {
  py::array_t<double> a(shape);
  std::copy(data.begin(), data.end(), a.mutable_data());
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

// The step callback of a run: `f` (a Python callable) called with a traverse.result.Step (rod
// runs) or BeamStep (beam runs) of the view, under the interpreter's lock. Stops the run when
// f returns False or raises; what it raised is kept in `raised` for run() to raise again once
// the run has stopped. `f` is borrowed (the caller's argument, alive for the run): no reference
// count changes without the lock.
template <class View, class MakeStep>
std::function<bool(const View&)> python_call(py::handle f, std::optional<py::error_already_set>& raised,
                                             MakeStep make) {
  return [f, &raised, make](const View& v) {
    py::gil_scoped_acquire gil;
    try {
      return f(make(v)).ptr() != Py_False;
    } catch (py::error_already_set& e) {
      raised.emplace(std::move(e));
      return false;
    }
  };
}

setup::StepCallback python_step_callback(bool beam, long every, py::handle f,
                                         std::optional<py::error_already_set>& raised) {
  setup::StepCallback cb;
  cb.every = every;
  if (beam) {
    cb.beam = python_call<setup::BeamStepView>(f, raised, [](const setup::BeamStepView& v) {
      const auto modes = static_cast<py::ssize_t>(v.q.size()), nodes = static_cast<py::ssize_t>(v.x.size());
      return py::module_::import("traverse.result")
          .attr("BeamStep")(v.t, v.step, frozen(v.q, {modes}), frozen(v.q_t, {modes}), frozen(v.x, {nodes}),
                            frozen(v.w, {nodes}));
    });
  } else {
    cb.rod = python_call<setup::RodStepView>(f, raised, [](const setup::RodStepView& v) {
      const py::ssize_t n = v.nodes;
      const py::module_ result = py::module_::import("traverse.result");
      py::object mass = py::none();
      if (v.has_mass)
        mass = v.has_body ? result.attr("MassStep")(v.sigma, v.speed, v.body, v.body_speed)
                          : result.attr("MassStep")(v.sigma, v.speed);
      return result.attr("Step")(v.t, v.step, frozen(v.r, {n, 3}), frozen(v.directors, {n, 3, 3}),
                                 frozen(v.u, {n, 3}), frozen(v.omega, {n, 3}), frozen(v.kappa, {n, 3}),
                                 frozen(v.n, {n, 3}), mass);
    });
  }
  return cb;
}

// How a run of run() ended early: the output file's status ("interrupted at ...") and the
// signal that stopped it (time::kStopRequested: the step callback).
using Stopped = std::pair<std::string, int>;

// Runs the scene into `output` as `traverse run SCENE -o OUTPUT [--overwrite] [-q]` does (with
// `restart`: as `traverse run --restart OUTPUT [SCENE]`, `s` empty for the scene stored in the
// file), on MPI_COMM_WORLD (every rank of an MPI launch calls it). The GIL is released while it
// runs. With `callback`, it is called every `every` time steps on rank 0 (python_step_callback).
// With `signals` (the interpreter's main thread), SIGINT and SIGTERM stop the run as they stop
// the executable (app::InterruptScope), and the interpreter's handlers are back afterwards.
// A run stopped by the callback or a signal returns the output file's status and the signal;
// a run that completed ("", 0). What the callback raised is raised again.
Stopped run(const std::optional<Source>& s, const std::string& output, bool overwrite, bool quiet, bool verbose,
            const std::string& invocation, bool restart, bool signals, long every, py::object callback) {
  std::optional<py::error_already_set> raised;
  Stopped stopped{"", 0};
  {
    py::gil_scoped_release nogil;
    std::lock_guard<std::mutex> lock(run_mutex());
    if (mpi_state().finished) throw std::runtime_error("traverse: the module was shut down (interpreter exit)");
    translated(
        [&] {
          ensure_mpi();
          const scene::Scene sc = !restart ? load(*s)
                                  : !s ? app::restart_scene(output, "", {})
                                  : s->is_file ? app::restart_scene(output, s->path_or_text, s->overrides)
                                               : load(*s);
          const bool beam = sc.model == scene::Model::Beam;
          const bool statics = !beam && sc.continuation.enabled;
          if (restart && statics)
            throw app::UsageError{"traverse.run(restart=" + output + "): continuation (statics) runs cannot be restarted"};
          app::RunOptions opt;
          opt.output = output;
          opt.restart = restart;
          opt.restart_interval = sc.output.restart_interval;
          opt.overwrite = overwrite;
          opt.quiet = quiet;
          opt.verbose = verbose && !quiet;
          opt.invocation = invocation;
          if (!callback.is_none()) {
            if (statics)
              throw std::invalid_argument("traverse.run: callback= is for runs with time steps; " + sc.file +
                                          " is a continuation (statics) scene");
            opt.on_step = python_step_callback(beam, every, callback, raised);
          }
          std::optional<app::InterruptScope> scope;
          if (signals) scope.emplace();
          try {
            app::run_scene(sc, opt, MPI_COMM_WORLD);
          } catch (const app::Interrupted& e) {
            output::set_file_status(e.output(), e.status(), MPI_COMM_WORLD);
            stopped = {e.status(), e.signal()};
          }
        },
        output);
  }
  if (raised) throw *raised;
  return stopped;
}

// A text known to rank 0, on every rank of `comm`.
std::string bcast_text(std::string text, MPI_Comm comm) {
  unsigned long length = text.size();
  MPI_Bcast(&length, 1, MPI_UNSIGNED_LONG, 0, comm);
  text.resize(length);
  MPI_Bcast(text.data(), static_cast<int>(length), MPI_CHAR, 0, comm);
  return text;
}

// Throws OutputError with rank 0's `error` on every rank when it is not empty.
void agree_on_error(const std::string& error, MPI_Comm comm) {
  const std::string e = bcast_text(error, comm);
  if (!e.empty()) throw output::OutputError(e);
}

// The arguments of a sweep as `traverse sweep` reads them from its command line.
struct SweepArgs {
  std::vector<std::pair<std::string, std::string>> vary;  // ("--vary" or "--with", "KEY=VALUES")
  std::vector<std::string> summaries;                      // --summary texts; the first goes to the index
  std::string directory;                                   // -o DIR; empty: a new temporary directory
  bool overwrite = false, quiet = true;
  bool signals = false;  // SIGINT and SIGTERM stop the sweep as they stop `traverse sweep` (app::InterruptScope)
  std::string invocation;
};

// What a sweep returns on every rank: its exit code (as `traverse sweep`'s), the index (the
// text of DIR/index.csv), the directory, the values of the summaries after the first (one
// list per summary, a value per case, NaN where the case did not complete), this rank and the
// signal that stopped the sweep (0: none; the largest of the ranks').
using SweepOutcome = std::tuple<int, std::string, std::string, std::vector<std::vector<double>>, int, int>;

// Runs the sweep of `s` as `traverse sweep SCENE -o DIR --vary ... [--summary S] [--overwrite]
// [-q]` does (app::plan_sweep, app::run_sweep) over MPI_COMM_WORLD, every rank calling it. A
// scene of text is written to DIR/scene.yaml first (the cases read it as a file). Refused
// arguments leave nothing behind: the temporary directory, or the scene file written.
SweepOutcome sweep(const Source& s, const SweepArgs& a) {
  py::gil_scoped_release nogil;
  std::lock_guard<std::mutex> lock(run_mutex());
  if (mpi_state().finished) throw std::runtime_error("traverse: the module was shut down (interpreter exit)");
  namespace fs = std::filesystem;
  return translated([&]() -> SweepOutcome {
    ensure_mpi();
    const MPI_Comm comm = MPI_COMM_WORLD;
    int rank = 0;
    MPI_Comm_rank(comm, &rank);
    // Everything the command line parses, parsed as it does (same messages).
    app::CommandLine cl;
    cl.command = app::CommandLine::Command::Sweep;
    for (const auto& [option, text] : a.vary) {
      cl.vary.push_back(app::parse_vary(text, option));
      cl.vary.back().with_previous = option == "--with";
    }
    std::vector<app::SummarySpec> summaries;
    for (const auto& text : a.summaries) summaries.push_back(app::parse_summary(text));
    if (!summaries.empty()) cl.summary = summaries.front();
    cl.overrides = s.overrides;
    cl.overwrite = a.overwrite;
    cl.quiet = a.quiet;
    cl.invocation = a.invocation;
    const bool temporary = a.directory.empty();
    std::string made;  // what to remove if the sweep is refused (rank 0)
    if (temporary) {
      std::string error;
      if (rank == 0) {
        std::string pattern = (fs::temp_directory_path() / "traverse-sweep-XXXXXX").string();
        if (mkdtemp(pattern.data())) made = pattern;
        else error = pattern + ": cannot make a temporary directory for the sweep";
      }
      agree_on_error(error, comm);
    }
    cl.output = temporary ? bcast_text(made, comm) : a.directory;
    cl.scene = s.is_file ? s.path_or_text : (fs::path(cl.output) / "scene.yaml").string();
    try {
      if (!s.is_file) {
        std::string error;
        if (rank == 0) {
          std::error_code ec;
          fs::create_directories(cl.output, ec);
          if (!a.overwrite && fs::exists(cl.scene)) {
            error = cl.scene + ": exists (use overwrite=True to replace the scene, the index and the case files)";
          } else {
            std::ofstream out(cl.scene);
            out << s.path_or_text;
            if (!out.flush()) error = cl.scene + ": cannot write the scene of the sweep";
            if (!temporary) made = cl.scene;
          }
        }
        agree_on_error(error, comm);
      }
      const app::SweepPlan plan = app::plan_sweep(cl);
      for (std::size_t i = 1; i < summaries.size(); ++i) {  // each checked as --summary would be
        app::CommandLine other = cl;
        other.summary = summaries[i];
        (void)app::plan_sweep(other);
      }
      std::optional<app::InterruptScope> scope;
      if (a.signals) scope.emplace();
      const int code = app::run_sweep(cl, plan, comm);
      const int signal = app::interrupt_requested(comm);
      scope.reset();
      made.clear();  // ran: the files are the sweep's
      std::string index;
      std::vector<std::vector<double>> more(summaries.size() > 1 ? summaries.size() - 1 : 0,
                                            std::vector<double>(plan.cases.size(), std::nan("")));
      if (rank == 0) {
        std::ifstream in(fs::path(cl.output) / "index.csv");
        index.assign(std::istreambuf_iterator<char>(in), {});
        for (std::size_t i = 0; i < more.size(); ++i)
          for (std::size_t k = 0; k < plan.cases.size(); ++k)
            if (fs::exists(plan.cases[k].output) && output::Reader(plan.cases[k].output).status() == "complete")
              more[i][k] = app::case_summary(plan.cases[k].output, summaries[i + 1]);
      }
      for (auto& values : more) MPI_Bcast(values.data(), static_cast<int>(values.size()), MPI_DOUBLE, 0, comm);
      return {code, bcast_text(index, comm), cl.output, more, rank, signal};
    } catch (...) {
      if (rank == 0 && !made.empty()) {
        std::error_code ignored;
        fs::remove_all(made, ignored);
      }
      throw;
    }
  });
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
        py::arg("verbose") = false, py::arg("invocation") = "", py::arg("restart") = false, py::arg("signals") = false,
        py::arg("every") = 1, py::arg("callback") = py::none(),
        "runs the scene (None with restart: the file's) into the HDF5 file `output` (app::run_scene), or continues "
        "it (restart), calling `callback` every `every` time steps; returns (status, signal) of a run a callback or "
        "a signal stopped, ('', 0) of one that completed; raises SceneError, OutputError, RunError");
  py::class_<SweepArgs>(m, "SweepArgs")
      .def(py::init<>())
      .def_readwrite("vary", &SweepArgs::vary)
      .def_readwrite("summaries", &SweepArgs::summaries)
      .def_readwrite("directory", &SweepArgs::directory)
      .def_readwrite("overwrite", &SweepArgs::overwrite)
      .def_readwrite("quiet", &SweepArgs::quiet)
      .def_readwrite("signals", &SweepArgs::signals)
      .def_readwrite("invocation", &SweepArgs::invocation);
  m.def("sweep", &sweep, py::arg("source"), py::arg("args"),
        "runs a sweep (app::plan_sweep, app::run_sweep): (exit code, index.csv text, directory, further "
        "summaries, rank, signal); raises SceneError, OutputError");
  m.def("finish", &finish, "ends Kokkos and, when this module started it, MPI (at the interpreter's exit)");
  m.def("mpi_started_here", [] { return mpi_state().started_here; }, "whether this module called MPI_Init_thread");
  m.attr("version") = version_string();
  m.attr("stop_requested") = time::kStopRequested;  // the signal number of a stop by the step callback
}
