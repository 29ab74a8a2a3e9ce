#pragma once
// The traverse scene: what a scene file may say (declared in scene.cpp, printed by
// `traverse check`) and the typed structs the rest of the code is built from.
#include <cstddef>
#include <stdexcept>
#include <array>
#include <string>
#include <vector>

#include "traverse/core/end_types.hpp"
#include "traverse/core/types.hpp"
#include "traverse/scene/schema.hpp"

namespace traverse::scene {

enum class Model { Beam, Rod };

// Every word a scene file may choose from is an enumerator here: the scene module turns the
// words into these once (the schema's choice lists are built from the same tables), and the
// rest of the code switches on them. enum_names<E>() lists the words in enumerator order;
// name_of(e) is the word of one enumerator.
enum class Supports { simply_supported, clamped_free, clamped_clamped, clamped_pinned };
enum class BeamIntegrator { rk4, newmark };
/// The end condition types and their parameters: declared in traverse/core/end_types.hpp.
using traverse::EndType;
enum class LoadType { moving_mass, moving_force, coupled_mass, sprung_mass, vehicle, axle_train };
/// How a coupled mass is held on the structure: threaded on it (bilateral) or resting on its
/// +d2 side (unilateral: it may lift off).
enum class Contact { bilateral, unilateral };
/// What takes the reaction of a coupled mass's resistance: nothing (air) or the structure.
enum class ResistanceThrough { air, structure };
enum class Entry { left, right };
enum class PlanarMode { automatic, on, off };
enum class InitialStateType { static_equilibrium, rest, file, arch };
enum class ContinuationParameter { end_load, end_position, gravity_factor, load_position, load_magnitude };
enum class ContinuationMethod { arclength, natural };
enum class ContinuationProbeType { point, end_compression };
enum class ProbeType { deflection, point, acceleration };
/// A vector quantity of the rod at a point (probes) or at every node (fields).
enum class Quantity { position, u, omega, kappa, n, m, d1, d2, d3, v };
enum class Frame { fixed, body };
/// rod.model: which strains of the centreline the rod admits (none, stretch, stretch and shear).
enum class RodStrain { inextensible, extensible, shearable };
/// Fields written at every node: rod (u .. R) and beam (deflection .. bending_moment).
enum class Field { u, omega, kappa, n, m, r, R, deflection, slope, bending_moment, v, stretch, axial_force };

template <class E>
const std::vector<std::string>& enum_names();
template <> const std::vector<std::string>& enum_names<Supports>();
template <> const std::vector<std::string>& enum_names<BeamIntegrator>();
template <> const std::vector<std::string>& enum_names<EndType>();
template <> const std::vector<std::string>& enum_names<LoadType>();
template <> const std::vector<std::string>& enum_names<Entry>();
template <> const std::vector<std::string>& enum_names<Contact>();
template <> const std::vector<std::string>& enum_names<ResistanceThrough>();
template <> const std::vector<std::string>& enum_names<PlanarMode>();
template <> const std::vector<std::string>& enum_names<InitialStateType>();
template <> const std::vector<std::string>& enum_names<ContinuationParameter>();
template <> const std::vector<std::string>& enum_names<ContinuationMethod>();
template <> const std::vector<std::string>& enum_names<ContinuationProbeType>();
template <> const std::vector<std::string>& enum_names<ProbeType>();
template <> const std::vector<std::string>& enum_names<Quantity>();
template <> const std::vector<std::string>& enum_names<Frame>();
template <> const std::vector<std::string>& enum_names<RodStrain>();
template <> const std::vector<std::string>& enum_names<Field>();

/// The scene-file word of an enumerator.
template <class E>
const std::string& name_of(E e) {
  return enum_names<E>().at(static_cast<std::size_t>(e));
}
/// The enumerator of a word (validated input); throws std::logic_error for an unknown word.
template <class E>
E enum_of(const std::string& word) {
  const auto& names = enum_names<E>();
  for (std::size_t i = 0; i < names.size(); ++i)
    if (names[i] == word) return static_cast<E>(i);
  throw std::logic_error("scene: '" + word + "' is not a known word here");
}

/// Cross-section properties derived from the declared shape.
struct SectionSpec {
  std::string shape;    ///< solid_circle, hollow_circle, rectangle, properties
  double area = 0.0;    ///< A [m^2]
  double I1 = 0.0;      ///< second moment about d1 (bending in the d2 direction) [m^4]
  double I2 = 0.0;      ///< second moment about d2 [m^4]
  double J = 0.0;       ///< torsion constant [m^4]
  double radius_ratio = 0.0;  ///< inner / outer radius (hollow_circle; 0 otherwise)
};

/// Small-deflection Euler–Bernoulli beam (bending in the (j, k) plane: I = I1).
struct BeamSpec {
  double length = 0.0;          ///< L [m]
  double youngs_modulus = 0.0;  ///< E [Pa]
  double density = 0.0;         ///< rho [kg/m^3]
  SectionSpec section;
  Supports supports = Supports::simply_supported;
  int modes = 3;                ///< Galerkin modes
  int quadrature_points = 6;    ///< Gauss points per mesh cell
  BeamIntegrator integrator = BeamIntegrator::rk4;
  bool self_weight = true;      ///< the beam's own weight acts (false: deflections about its static sag)
  /// Structural damping (beam.damping): none, modal ratios (one for every mode, or one per
  /// mode), or Rayleigh coefficients a [1/s] (mass) and b [s] (stiffness).
  enum class Damping { none, ratios, rayleigh } damping = Damping::none;
  std::vector<double> damping_ratios;
  double rayleigh_mass = 0.0, rayleigh_stiffness = 0.0;
  double mass() const { return density * section.area * length; }  ///< beam mass [kg]
};

/// Cosserat rod, initially straight along k in the (j, k) plane: inextensible and unshearable,
/// extensible, or extensible and shearable (rod.model).
struct RodSpec {
  double length = 0.0;          ///< L [m]
  double youngs_modulus = 0.0;  ///< E [Pa]
  double shear_modulus = 0.0;   ///< G [Pa] (from the Poisson ratio when that is given)
  double density = 0.0;         ///< rho [kg/m^3]
  SectionSpec section;
  Vec3 intrinsic_curvature = Vec3::Zero();  ///< kappa0, body components [1/m]
  RodStrain strain = RodStrain::inextensible;  ///< rod.model
  /// Shear coefficient k: rod.shear_coefficient, else Cowper's of the section (solid and hollow
  /// circle, rectangle; 0 for a `properties` section, which must give it for a shearable rod).
  double shear_coefficient = 0.0;
  double axial_stiffness = 0.0;  ///< E A, or rod.axial_stiffness [N]
  double shear_stiffness = 0.0;  ///< k G A, or rod.shear_stiffness [N] (0 when k is unknown)
  /// rod.damping: Kelvin-Voigt viscosities of the stretch and the shear [N s], of bending and
  /// of torsion [N m^2 s] (zero: none).
  double damping_axial = 0.0, damping_shear = 0.0, damping_bending = 0.0, damping_torsion = 0.0;
  double mass() const { return density * section.area * length; }
};

/// One end condition of the rod (fixed-frame vectors), traverse/core/end_types.hpp.
using traverse::EndSpec;

/// A load that travels along the structure.
struct MovingLoadSpec {
  std::string name;
  LoadType type = LoadType::moving_force;
  bool inertia = false;    ///< true for a moving mass
  double mass = 0.0;       ///< M [kg] (0 for a force given directly)
  Vec3 force = Vec3::Zero();  ///< fixed-frame force [N] (M g (-j) for a mass or a weight)
  double speed = 0.0;      ///< speed at entry_time [m/s], >= 0, along the direction of travel
  double acceleration = 0.0;  ///< [m/s^2] along the direction of travel
  Entry entry = Entry::left;  ///< left: travels towards +s; right: towards -s
  double start = 0.0;      ///< position at entry_time [m]
  double entry_time = 0.0;    ///< [s]
  // coupled_mass (type LoadType::coupled_mass): the mass moves by itself along the structure
  // (docs/rod.md, "Coupled mass"). Its initial velocity along +s is direction() * speed (entry
  // left for a velocity >= 0, right for one < 0), acceleration 0 and entry_time 0: the
  // motion functions above give the uncoupled, constant-speed path, used only for the
  // up-front limits (dt auto, speed checks), never for the physics.
  bool coupled = false;         ///< type coupled_mass
  double drive = 0.0;           ///< constant force along the tangent d3 [N] (a robot's traction)
  double resistance = 0.0;      ///< viscous resistance c >= 0: force -c sigma' d3 [N s/m]
  ResistanceThrough resistance_through = ResistanceThrough::air;  ///< who takes its reaction
  double friction = 0.0;        ///< Coulomb friction coefficient mu >= 0
  Contact contact = Contact::bilateral;
  // sprung_mass and vehicle (docs/beam.md): a body (mass = its mass M_v) on axles, each
  // with a suspension; the motion functions give the leading axle's path.
  double pitch_inertia = 0.0;        ///< J_v [kg m^2] (vehicle)
  std::vector<double> axle_offsets;  ///< e_a [m] from the body's centre, positive ahead
  std::vector<double> axle_stiffness, axle_damping, wheel_masses;  ///< per axle [N/m], [N s/m], [kg]
  // axle_train: moving forces P_a [N] (positive down) at e_a [m] behind the head (the first axle).
  std::vector<double> train_offsets, train_loads;
  /// Whether the load carries a body on suspensions (sprung_mass, vehicle).
  bool suspended() const { return type == LoadType::sprung_mass || type == LoadType::vehicle; }
  /// Whether a rod steps the load with itself by a partitioned iteration (rod::CoupledRodStepper:
  /// a coupled_mass, or a sprung_mass), rather than carrying it as a load of its model.
  bool stepped_with_rod() const { return coupled || type == LoadType::sprung_mass; }
  /// Distance [m] from the leading to the trailing axle (0 for a single point load).
  double extent() const;
  /// Initial velocity along +s [m/s] (coupled_mass).
  double initial_velocity() const { return direction() * speed; }
  int direction() const { return entry == Entry::left ? +1 : -1; }
  /// Position [m] at time t >= entry_time (also beyond the ends).
  double position(double t) const;
  double velocity(double t) const;  ///< signed [m/s]
  /// The largest speed [m/s] while on a structure of length L, up to t_end (t_end < 0: until
  /// it leaves): at entry, or where it leaves (or at t_end) when it accelerates.
  double fastest_speed(double length, double t_end) const;
  /// Time at which the load (its trailing axle) reaches the far end of a structure of length L, or +inf.
  double exit_time(double length) const;
  /// Time at which the load has travelled the distance d >= 0 from `start` along its
  /// direction, or +inf if it never does (it stops before).
  double travel_time(double d) const;
  /// Where the load is at time t: position(t) once it has started, NaN before entry_time
  /// (it may lie beyond the ends; the models take it as off the structure there).
  double sigma(double t) const;
};

struct MeshSpec {
  int nodes = 0;    ///< N + 1 nodes
  double ds = 0.0;  ///< uniform spacing [m]
};

/// Step sizes chosen by a local error estimate (time.adaptive; docs/adaptive.md).
struct AdaptiveSpec {
  bool enabled = false;
  double tolerance = 0.0;  ///< relative tolerance on the local error
  /// Rod: the controlled quantities and their absolute tolerances, in the order position [m],
  /// orientation [rad], u [m/s], omega [rad/s], kappa [1/m] (rod::ErrorGroup).
  std::array<bool, 5> controlled{true, true, false, false, false};
  std::array<double, 5> absolute{0.0, 0.0, 0.0, 0.0, 0.0};
  double dt_min = 0.0;  ///< [s] (resolved: 1e-6 time.dt when not given)
  double dt_max = 0.0;  ///< [s] 0: no bound but the output interval
  double growth = 2.0, shrink = 0.2, safety = 0.9;
  int newton_target = 6;
  bool land_on_nodes = true;  ///< rod: steps end at the node crossings of prescribed moving loads
};

struct TimeSpec {
  bool dt_auto = true;
  double dt = 0.0;   ///< [s] (resolved by the runner when dt_auto); adaptive: the first step
  bool end_auto = true;
  double end = 0.0;  ///< [s] (resolved by the runner when end_auto)
  /// time.end: auto with a coupled_mass: the run ends at the mass's first event; `end` is then
  /// time.auto_limit, the latest end (end_auto is false: the end is a number).
  bool end_at_event = false;
  AdaptiveSpec adaptive;
};

/// Generalised-alpha parameters of the rod scheme.
struct SchemeSpec {
  double rho_inf = 1.0;        ///< spectral radius in time (1: no numerical damping)
  double rho_inf_space = 1.0;  ///< spectral radius in space (1: plain box scheme in s)
  bool explicit_parameters = false;  ///< the six parameters below were given directly
  double as = 0.5, bs = 0.5, gs = 0.5, at = 0.5, bt = 0.5, gt = 0.5;
  /// Planar fast path: automatic (when the scene is planar), on (required), off (always 3D).
  PlanarMode planar = PlanarMode::automatic;
};

struct InitialStateSpec {
  /// static: equilibrium under the dead loads; rest: straight, unloaded; file: a state saved
  /// by a continuation run; arch: the arch formation pipeline (buckle, pin at end_to_end,
  /// raise gravity).
  InitialStateType type = InitialStateType::static_equilibrium;
  std::string file;         ///< type file: the continuation output file
  std::string state;        ///< type file: the state's name in it (default "final")
  double end_to_end = 0.0;  ///< type arch: end-to-end distance dz [m]
  bool loaded = false;      ///< type arch: in equilibrium with the load on the arch at t = 0
};

/// A scalar measured on each static state of a continuation run.
struct ContinuationProbeSpec {
  std::string name;
  ContinuationProbeType type = ContinuationProbeType::point;
  double at = 0.0;        ///< point: arclength [m]
  Quantity quantity = Quantity::position;  ///< point: position, kappa, n, m, d1, d2, d3
  int component = 0;      ///< point: 0, 1, 2 (x, y, z or 1, 2, 3)
  Frame frame = Frame::fixed;  ///< point
};

/// Continuation of static states (a scene with this section runs statics, not dynamics).
struct ContinuationSpec {
  bool enabled = false;
  ContinuationParameter parameter = ContinuationParameter::end_load;
  bool start_given = false;
  double start = 0.0;     ///< start value of the parameter
  double stop = 0.0;      ///< the run ends where the parameter reaches this bound
  double step = 0.0;      ///< initial step size (positive; the direction is towards stop)
  double min_step = 0.0, max_step = 0.0;
  ContinuationMethod method = ContinuationMethod::arclength;
  int max_steps = 0;
  bool stability = true;
  int eigenvalues = 6;
  bool switch_branches = true;
  double branch_amplitude = 0.0;  ///< [m]
  std::vector<ContinuationProbeSpec> probes;
};

struct OutputProbeSpec {
  std::string name;
  ProbeType type = ProbeType::point;  ///< deflection (beam) or point (rod)
  double at = 0.0;       ///< position along the structure [m]
  Quantity quantity = Quantity::position;  ///< point
  Frame frame = Frame::fixed;  ///< point: fixed or body components
};

struct OutputSpec {
  std::string file;  ///< HDF5 output path
  int every = 1;     ///< write every this many steps (plus the first and the last state); 1 when every_auto
  bool every_auto = true;  ///< output.every: auto (the beam's runner resolves it: run_limits.hpp beam_output_every)
  double restart_interval = 60.0;  ///< wall seconds between rod restart points (0: every output step)
  double flush_interval = 1.0;     ///< wall seconds between flushes of the output file (0: every output step)
  double progress_interval = 1.0;  ///< wall seconds between progress reports (0: every time step)
  std::vector<OutputProbeSpec> probes;
  std::vector<Field> fields;
};

struct Scene {
  std::string file;   ///< scene file path as given
  std::string text;   ///< the validated scene, every default filled in, as YAML
  ValidatedTree tree;
  Model model = Model::Beam;
  std::string title;
  double gravity = 0.0;  ///< g [m/s^2], acting along -j
  MeshSpec mesh;
  BeamSpec beam;         ///< model beam
  RodSpec rod;           ///< model rod
  EndSpec left, right;   ///< model rod
  SchemeSpec scheme;     ///< model rod
  InitialStateSpec initial_state;  ///< model rod
  ContinuationSpec continuation;   ///< model rod
  std::vector<MovingLoadSpec> loads;
  TimeSpec time;
  OutputSpec output;
  /// The structure's length [m] (beam or rod).
  double length() const { return model == Model::Beam ? beam.length : rod.length; }
  /// The `solver` section, passed to the solver module (model rod); std::logic_error for a
  /// scene not made by parse_scene.
  const Teuchos::ParameterList& solver_parameters() const;
  /// Whether the validated scene holds the key `key_path` ("mesh.ds", "loads.truck.mass"):
  /// given in the file or by --set, or filled in by its default (false for a scene not made
  /// by parse_scene).
  bool has(const std::string& key_path) const;
};

/// The root of the scene schema.
const Param& scene_schema();

/// Reads, overrides and validates a scene file; throws SceneError on any bad input
/// (unreadable file included). `overrides` are "key.path=value" strings (--set).
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});

/// Same from text already in memory (`file_name` is used in messages).
Scene parse_scene(const std::string& yaml_text, const std::string& file_name,
                  const std::vector<std::string>& overrides = {});

/// The complete scene, every default filled in and documented (for `traverse check`).
std::string describe_scene(const Scene& scene, bool with_comments = true);

/// Documentation of every registered type (end conditions, loads, probes, sections).
std::string describe_types();

/// The prescribed loads (moving forces and masses, not coupled ones) that are on the structure
/// at t = 0 with a non-zero force (what initial_state.loaded puts into the arch's start).
std::vector<const MovingLoadSpec*> prescribed_loads_at_start(const Scene& scene);

/// Throws SceneError located at `key_path` of the scene ("<file>:<line>:<col>: <key>:
/// expected <expected>, found <found>"), for problems found after validation.
[[noreturn]] void fail_at(const Scene& scene, const std::string& key_path, const std::string& expected,
                          const std::string& found);

}  // namespace traverse::scene
