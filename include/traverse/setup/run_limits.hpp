#pragma once
// What a run will cost, estimated from the validated scene before anything large is allocated,
// and the limits it must fit (docs/reliability.md, "Limits"): the time grid (step count),
// the memory per rank, the counters, and the load against the stiffness. Each check throws
// scene::SceneError located at the key that decides it (exit code 2). Pure functions of the
// scene: no MPI, no Trilinos (the fuzz target calls them too); memory_limit.hpp finds what the
// machine allows.
#include <cmath>
#include <string>
#include <vector>

#include "traverse/beam/beam_simulation.hpp"
#include "traverse/beam/mode_set.hpp"
#include "traverse/beam/uniform_modes.hpp"
#include "traverse/core/time_grid.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::setup {

/// Default of --max-steps: a sanity limit on the number of time steps (10^7: about 6 hours
/// of the default scene's 101-node rod, far beyond any scene in inputs/).
constexpr long kDefaultMaxSteps = 10000000;

/// The largest load ratio W L^2 / (E I) a run accepts: 1 / machine epsilon (4.5e15). Beyond
/// it the bending stiffness E I kappa changes the moment balance by less than the rounding
/// of the load's moment W L in double precision: the stiffness is numerically absent.
constexpr double kMaxLoadRatio = 4503599627370496.0;

/// Limits given on the command line.
struct RunLimits {
  double max_memory = 0.0;            ///< --max-memory [bytes per rank]; 0: what the machine allows
  long max_steps = kDefaultMaxSteps;  ///< --max-steps
  std::string memory_source;          ///< where max_memory comes from when not --max-memory (sweep cases)
};

/// The time grid of a dynamic run and the keys that decide it.
struct TimePlan {
  double dt = 0.0, t_end = 0.0;
  double steps = 0.0;         ///< grid_step_count (may be huge or NaN before the check)
  TimeGrid grid;              ///< valid after check_time_plan
  std::string dt_text;        ///< "time.dt = 0.001 s" or "time.dt: auto = mesh.ds / loads.F.speed = ... s"
  std::string end_text;       ///< likewise for the end time
  std::vector<std::string> dt_keys, end_keys;  ///< the keys that decide each, most specific first
  bool entry_dominated = false;  ///< time.end auto and mostly a load's entry_time
  bool dt_from_modes = false;    ///< beam time.dt auto from the highest mode (not capped by a load)
  int every = 1;                 ///< output.every, resolved (beam auto: beam_time_plan)
  std::string every_text;        ///< "output.every = 10" or "output.every: auto = ..."
  /// The output steps written: the first state, every `every` steps, the last state.
  double output_steps() const { return std::floor(steps / every) + 1.0 + (std::fmod(steps, every) > 0.0 ? 1.0 : 0.0); }
};

/// Outputs per period of the fastest motion a beam run keeps (its highest mode, or a faster
/// suspension) when output.every is auto: twice the Nyquist rate, so that every mode kept is
/// in the output without aliasing and its peaks within cos(pi / 4) of their value.
constexpr double kBeamOutputsPerPeriod = 4.0;

/// The rod's grid: time.dt (auto resolved by the scene: ds / v), time.end or the time the last
/// load leaves; a remainder below 1e-6 dt joins the last step.
TimePlan rod_time_plan(const scene::Scene& sc);
/// The beam's grid: time.dt or auto (a twentieth of the period of the highest mode, at most
/// the time a load needs to cross a cell), time.end or when the last load leaves.
TimePlan beam_time_plan(const scene::Scene& sc);

/// The estimated size of a run's output: the HDF5 file and its XDMF sidecar [bytes].
struct OutputSize {
  double h5 = 0.0, xmf = 0.0;
  std::string text() const;  ///< "about 2.7 MiB (+ 0.64 MiB .xmf sidecar)"
};
/// From the time plan's output steps, the fields (per node and step: the values and the
/// sidecar's copies of its arrays) and the probes; within about 25 % of the files written.
OutputSize output_size(const scene::Scene& sc, const TimePlan& plan);

/// Throws SceneError unless dt and the end time are positive and finite and the step count
/// is at most max_steps and kMaxGridSteps; fills plan.grid.
void check_time_plan(const scene::Scene& sc, TimePlan& plan, long max_steps);

/// A memory estimate of one rank [bytes] with its parts, for the message.
struct MemoryPlan {
  double bytes = 0.0;
  std::string detail;             ///< how it was obtained (nodes, bytes per node, path, solver)
  std::vector<std::string> keys;  ///< the keys that decide it
};

/// The rod's path for the estimate.
struct RodPathGuess {
  bool planar = false;    ///< the planar path is expected (scheme.planar on, or auto and planar)
  int ranks = 1;
};
/// Peak resident memory of one rank of a rod run (dynamics or continuation).
MemoryPlan rod_memory(const scene::Scene& sc, const RodPathGuess& path);
/// Peak resident memory of one rank of a beam run.
MemoryPlan beam_memory(const scene::Scene& sc, int ranks);

/// What one rank may use [bytes], and where the figure comes from.
struct MemoryLimit {
  double bytes = 0.0;   ///< <= 0: no limit known
  std::string source;   ///< "--max-memory 4G" or "MemAvailable of this host (...) / 2 ranks on it"
};
/// Throws SceneError when plan.bytes exceeds the limit.
void check_memory(const scene::Scene& sc, const MemoryPlan& plan, const MemoryLimit& limit);

/// Throws SceneError when a count of the run does not fit the integers that hold it (local
/// unknowns of a rank in int, a gathered rod state in an int MPI count).
void check_counters(const scene::Scene& sc, const RodPathGuess& path);

/// Throws SceneError when a derived property of the structure is not a positive finite number
/// though its inputs are (a product that underflows to 0 or overflows: rho A, E I, G J, the
/// section's A and I from tiny or huge dimensions); the models divide by them.
void check_properties(const scene::Scene& sc);

/// The load ratio W L^2 / (E I) of a scene: W the largest of the point loads, the mass weights,
/// the structure's weight and a roller end's force; `what` says which, `keys` its keys.
struct LoadRatio {
  double ratio = 0.0, W = 0.0, EI = 0.0;
  std::string what;
  std::vector<std::string> keys;
};
LoadRatio load_ratio(const scene::Scene& sc);

/// Throws SceneError when the load ratio W L^2 / (E I) exceeds kMaxLoadRatio (W: the largest
/// of the point loads, the mass weights, the structure's weight and a roller end's force).
void check_load_ratio(const scene::Scene& sc);

/// The beam module's supports of a scene's.
beam::Support beam_support(scene::Supports s);

/// The speed of light [m/s]: the largest speed a load may have while it is on the structure.
constexpr double kSpeedOfLight = 299792458.0;

/// Throws SceneError when a load moves faster than light while it is on the structure (its
/// speed at entry, or at the far end when it accelerates): no load does, and far beyond it
/// the moving-load terms (M v^2) and the time steps (dt = ds / v) leave double precision.
void check_load_speeds(const scene::Scene& sc);

/// The small-deflection range of the beam model (docs/beam.md "Validity"): |w| <= L / 10 and
/// |w_x| <= 0.2. Beyond it the terms the linear theory drops (the curvature's factor
/// (1 + w_x^2)^(3/2), the axial shortening w_x^2 / 2) change the answer by more than about 6 %.
constexpr double kMaxBeamDeflectionRatio = 0.1;
constexpr double kMaxBeamSlope = 0.2;

/// Throws SceneError when the beam's static deflection under its own weight (where every beam
/// run starts) already leaves the small-deflection range: closed forms of the uniform load on
/// the scene's supports. Keys: beam.youngs_modulus, beam.section, beam.density, gravity.
void check_beam_static_deflection(const scene::Scene& sc);

/// The small-deflection check of a running beam: the largest |w| and |w_x| over 8 points per
/// mode (and the ends) at an output time, from the modes at those points evaluated once (two
/// matrix-vector products per check). `why` gives the message of a state outside the range
/// (the figures, the bound, the keys that decide it), or "" for a state inside. A deflection
/// above 10 times the largest static deflection the loads can cause (the beam's weight and
/// every load's force at its worst place, closed forms: twice that is the most a suddenly
/// applied load gives) is no physics but an unstable integration, and is reported as such.
class BeamDeflectionCheck {
 public:
  BeamDeflectionCheck(const scene::Scene& sc, const beam::ModeSet& modes);
  /// At modal coordinates Y (the beam's n modes) at time t.
  std::string why(double t, const VecX& Y) const;

 private:
  struct Extreme {
    double value = 0.0, at = 0.0;
  };
  std::string message(double t, const Extreme& w, const Extreme& slope) const;
  const scene::Scene& sc_;
  std::vector<double> points_;
  Eigen::MatrixXd phi_, dphi_;  ///< the modes and their slopes at the points (points x modes)
  double static_bound_ = 0.0;   ///< the largest static deflection the loads can cause [m]
};

/// Warnings for the loads that can do nothing (docs/reliability.md "Runs outside what the
/// models answer"): a load whose force is zero (a moving mass, or a force given as a weight,
/// with gravity: 0; a force_vector of zero) and that has no drive, or that enters at or after a given
/// time.end; one line per load naming its keys. A structure at rest under no load
/// stays at rest: such a run computes nothing the scene meant.
std::vector<std::string> idle_load_warnings(const scene::Scene& sc);

/// Warnings for the loads a rod run's time grid under-resolves: a load that crosses more than
/// one cell per time step is resolved by the space grid but not in time; the run goes on (it
/// converges as dt falls). One line per load naming its keys.
std::vector<std::string> under_resolved_load_warnings(const scene::Scene& sc, const TimeGrid& g);

/// `traverse check`'s warnings for a rod scene with time.adaptive where measured runs of its
/// kind found fixed steps cheaper at equal error (docs/adaptive.md "Work and precision"): loads
/// at constant speed on a rod that is not formed into an arch (the hanging cables), a coupled
/// mass without friction (the bead, the inspection robot). Empty when adaptive steps pay or
/// nothing was measured.
std::vector<std::string> adaptive_warnings(const scene::Scene& sc);

/// Bytes as "512 MiB", "3.2 GiB".
std::string format_bytes(double bytes);
/// "4G", "512M", "1.5T", "1000000" -> bytes (K, M, G, T: powers of 1024; a trailing B or iB is
/// allowed); returns a negative value for anything else.
double parse_bytes(const std::string& text);

/// The key under which a load's magnitude is given: loads.<name>.force, force_vector, mass or
/// mass_fraction.
std::string load_magnitude_key(const scene::Scene& sc, const scene::MovingLoadSpec& l);

/// The first key of `keys` that was set by --set, else the first key (where a message
/// is located).
std::string deciding_key(const scene::Scene& sc, const std::vector<std::string>& keys);

}  // namespace traverse::setup
