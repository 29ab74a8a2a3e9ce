#pragma once
// The traverse scene: what a scene file may say (declared in scene.cpp, printed by
// `traverse check`) and the typed structs the rest of the code is built from.
#include <string>
#include <vector>

#include "traverse/scene/schema.hpp"

namespace traverse::scene {

enum class Model { Beam, Rod };

/// Cross-section properties derived from the declared shape.
struct SectionSpec {
  std::string shape;       ///< solid_circle, hollow_circle, rectangle, properties
  double area = 0.0;       ///< A [m^2]
  double second_moment = 0.0;  ///< I about the bending axis [m^4]
};

/// Small-deflection Euler–Bernoulli beam.
struct BeamSpec {
  double length = 0.0;          ///< L [m]
  double youngs_modulus = 0.0;  ///< E [Pa]
  double density = 0.0;         ///< rho [kg/m^3]
  SectionSpec section;
  std::string supports;         ///< simply-supported, clamped-free, clamped-clamped, clamped-pinned
  int modes = 3;                ///< Galerkin modes
  int quadrature_points = 4;    ///< Gauss points per mesh cell
  double mass() const { return density * section.area * length; }  ///< beam mass [kg]
};

/// A load that travels along the structure.
struct MovingLoadSpec {
  std::string name;
  std::string type;        ///< moving_mass or moving_force
  bool inertia = false;    ///< true for a moving mass
  double mass = 0.0;       ///< M [kg] (moving_mass; moving_force given by weight)
  double force = 0.0;      ///< downward force magnitude [N] (M g for a mass)
  double speed = 0.0;      ///< entry speed [m/s], >= 0, along the direction of travel
  double acceleration = 0.0;  ///< [m/s^2] along the direction of travel
  std::string entry;       ///< "left" (x = 0, moving towards +x) or "right" (x = L, towards -x)
  double entry_time = 0.0;    ///< [s]
};

struct MeshSpec {
  int nodes = 0;   ///< N + 1 nodes
  double ds = 0.0;  ///< uniform spacing [m]
};

struct TimeSpec {
  std::string integrator;  ///< rk4 or newmark (beam)
  bool dt_auto = true;
  double dt = 0.0;         ///< [s], resolved when dt_auto (see the scene documentation)
  bool end_auto = true;
  double end = 0.0;        ///< [s], resolved when end_auto
};

struct ProbeSpec {
  std::string name;
  std::string type;  ///< deflection
  double at = 0.0;   ///< position along the structure [m]
};

struct OutputSpec {
  std::string file;  ///< HDF5 output path (relative to the working directory)
  int every = 1;     ///< write every this many steps (plus the first and the last state)
  std::vector<ProbeSpec> probes;
  std::vector<std::string> fields;
};

struct Scene {
  std::string file;   ///< scene file path as given
  std::string text;   ///< the validated scene, every default filled in, as YAML
  ValidatedTree tree;
  Model model = Model::Beam;
  std::string title;
  double gravity = 0.0;  ///< g [m/s^2], acting along -j
  MeshSpec mesh;
  BeamSpec beam;
  std::vector<MovingLoadSpec> loads;
  TimeSpec time;
  OutputSpec output;
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

}  // namespace traverse::scene
