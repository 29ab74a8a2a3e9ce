// Scene reading and validation: every error path names the file, the key path, what was
// expected and what was found.
#include <gtest/gtest.h>

#include <Teuchos_ParameterList.hpp>

#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "traverse/scene/scene.hpp"

using namespace traverse::scene;

namespace {

const char* kBeam = R"(model: beam
title: test beam
beam:
  length: 2.0
  youngs_modulus: 2.0e11
  density: 7850
  section: {type: hollow_circle, outer_radius: 0.1, inner_radius: 0.05}
  supports: clamped-free
loads:
  m:
    type: moving_mass
    mass_fraction: 0.2
    speed: 50
output:
  probes:
    tip: {type: deflection, at: 2.0}
)";

// Parses kBeam with overrides and returns the error message ("" when valid).
std::string error_of(const std::vector<std::string>& overrides, const std::string& text = kBeam) {
  try {
    parse_scene(text, "scene.yaml", overrides);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

void expect_error(const std::vector<std::string>& overrides, const std::vector<std::string>& fragments,
                  const std::string& text = kBeam) {
  const std::string msg = error_of(overrides, text);
  ASSERT_FALSE(msg.empty()) << "no error for overrides";
  EXPECT_EQ(msg.rfind("scene.yaml", 0), 0u) << "message must start with the file name: " << msg;
  for (const auto& f : fragments) EXPECT_NE(msg.find(f), std::string::npos) << "missing '" << f << "' in: " << msg;
  std::cout << "  message: " << msg << "\n";
}

}  // namespace

TEST(Scene, ValidSceneFillsDefaultsAndDerivedValues) {
  const Scene s = parse_scene(kBeam, "scene.yaml");
  EXPECT_EQ(s.model, Model::Beam);
  EXPECT_DOUBLE_EQ(s.gravity, 9.8);
  EXPECT_EQ(s.beam.modes, 3);
  EXPECT_EQ(s.mesh.nodes, 101);
  EXPECT_NEAR(s.beam.section.area, M_PI * (0.01 - 0.0025), 1e-15);
  ASSERT_EQ(s.loads.size(), 1u);
  const double beam_mass = 7850 * s.beam.section.area * 2.0;
  EXPECT_NEAR(s.loads[0].mass, 0.25 * beam_mass, 1e-9);  // p/(1-p) with p = 0.2
  EXPECT_NEAR(s.loads[0].mass / (s.loads[0].mass + beam_mass), 0.2, 1e-12);
  EXPECT_TRUE(s.loads[0].inertia);
  EXPECT_EQ(s.loads[0].entry, Entry::left);
  EXPECT_TRUE(s.time.dt_auto);
  EXPECT_TRUE(s.time.end_auto);
  EXPECT_EQ(s.output.file, "scene.h5");
  ASSERT_EQ(s.output.probes.size(), 1u);
  EXPECT_EQ(s.output.probes[0].name, "tip");
}

TEST(Scene, DescribeListsEveryKeyWithDocumentation) {
  const Scene s = parse_scene(kBeam, "scene.yaml");
  const std::string d = describe_scene(s);
  for (const char* f : {"youngs_modulus: 200000000000", "[Pa]", "modes: 3", "default 3", "integrator: rk4",
                        "# mesh.", "type: moving_mass", "speed: 50", "[m/s]", "acceleration: 0", "fields: []"}) {
    if (std::string(f) == "# mesh.") continue;
    EXPECT_NE(d.find(f), std::string::npos) << "missing '" << f << "' in\n" << d;
  }
  // The described scene is itself a valid scene giving the same values.
  const Scene again = parse_scene(d, "described.yaml");
  EXPECT_EQ(describe_scene(again), d);
  EXPECT_NE(describe_types().find("moving_force"), std::string::npos);
}

TEST(Scene, OverridesApplyWithTheSameValidation) {
  const Scene s = parse_scene(kBeam, "scene.yaml", {"beam.modes=7", "loads.m.speed=100", "time.dt=1e-5"});
  EXPECT_EQ(s.beam.modes, 7);
  EXPECT_DOUBLE_EQ(s.loads[0].speed, 100.0);
  EXPECT_FALSE(s.time.dt_auto);
  EXPECT_DOUBLE_EQ(s.time.dt, 1e-5);
  expect_error({"beam.modes=-2"}, {"beam.modes", "expected a whole number in [1, 200]", "found '-2'"});
  expect_error({"beam.modes=-2"}, {"scene.yaml (set by --set beam.modes)"});
  const std::string msg = error_of({"beam.modes"});
  EXPECT_NE(msg.find("--set beam.modes: expected KEY.PATH=VALUE"), std::string::npos) << msg;
}

TEST(Scene, SyntaxErrorGivesLineAndColumn) {
  expect_error({}, {"scene.yaml:3:1", "well-formed YAML"}, "model: beam\nbeam: [1, 2\n");
}

TEST(Scene, UnknownKeySuggestsTheClosestOne) {
  expect_error({"beam.lenght=3"}, {"beam.lenght", "unknown key 'lenght'", "did you mean 'length'"});
  expect_error({"gravty=1"}, {"gravty", "did you mean 'gravity'"});
}

TEST(Scene, UnknownKeyHasItsLine) {
  std::string t = kBeam;
  t += "bogus: 1\n";
  expect_error({}, {"scene.yaml:17:1: bogus", "unknown key"}, t);
}

TEST(Scene, WrongTypes) {
  expect_error({"beam.length=long"}, {"beam.length", "a finite real number > 0 [m]", "found 'long'"});
  expect_error({"beam.modes=2.5"}, {"beam.modes", "whole number", "'2.5'"});
  expect_error({"beam={a: 1}"}, {"beam.a", "unknown key"});
  expect_error({"beam=3"}, {"beam", "expected a map of keys", "found '3'"});
  expect_error({"output.fields=[deflection, stress]"}, {"output.fields[1]", "one of {deflection", "'stress'"});
}

TEST(Scene, NonFiniteAndOutOfRange) {
  expect_error({"beam.density=.nan"}, {"beam.density", "not finite"});
  expect_error({"beam.youngs_modulus=.inf"}, {"beam.youngs_modulus", "not finite"});
  expect_error({"beam.length=0"}, {"beam.length", "> 0", "found '0'"});
  expect_error({"gravity=-1"}, {"gravity", ">= 0", "found '-1'"});
  expect_error({"loads.m.mass_fraction=1.0"}, {"loads.m.mass_fraction", "in (0, 1)"});
}

TEST(Scene, MissingRequiredKey) {
  std::string t = kBeam;
  t.replace(t.find("  density: 7850\n"), 16, "");
  expect_error({}, {"beam.density", "required key 'density' is missing"}, t);
  expect_error({}, {"model", "required"}, "beam: {}\n");
}

TEST(Scene, UnknownTypeNamesListTheKnownOnes) {
  expect_error({"loads.m.type=moving_mas"}, {"loads.m.type", "one of {axle_train, coupled_mass, moving_force, moving_mass, sprung_mass, vehicle}", "did you mean 'moving_mass'"});
  expect_error({"beam.section.type=square"}, {"beam.section.type", "cross-section type"});
  expect_error({"beam.supports=free-free"}, {"beam.supports", "one of {simply-supported"});
  expect_error({"model=plate"}, {"model", "one of {beam, rod}"});
}

TEST(Scene, Contradictions) {
  expect_error({"loads.m.mass=3"}, {"loads.m", "exactly one of 'mass' and 'mass_fraction'", "both"});
  expect_error({"mesh.nodes=11", "mesh.ds=0.2"}, {"mesh.ds", "either 'nodes' or 'ds'"});
  expect_error({"mesh.ds=0.3"}, {"mesh.ds", "divides the length 2"});
  expect_error({"beam.section.inner_radius=0.2"}, {"beam.section.inner_radius", "smaller than outer_radius"});
  expect_error({"output.probes.tip.at=2.5"}, {"output.probes.tip.at", "a position on the structure"});
  expect_error({"loads.m.speed=0"}, {"loads.m.speed", "moves"});
  expect_error({"loads.f={type: moving_force, speed: 1}"}, {"loads.f", "exactly one of 'force', 'force_vector', 'mass' and 'mass_fraction'", "none"});
}

TEST(Scene, DuplicateKeysAndBadNames) {
  expect_error({}, {"beam.length", "each key once"},
               "model: beam\nbeam:\n  length: 1\n  length: 2\n");
  expect_error({"loads={a.b: {type: moving_force, force: 1, speed: 1}}"}, {"loads.a.b", "without dots"});
}

TEST(Scene, AutoEndNeedsALoad) {
  std::string t = kBeam;
  t.replace(t.find("loads:"), t.find("output:") - t.find("loads:"), "");
  expect_error({}, {"time.end", "no loads"}, t);
  EXPECT_EQ(error_of({"time.end=0.1"}, t), "");
}

TEST(Scene, UnreadableFile) {
  try {
    load_scene("/nonexistent/scene.yaml");
    FAIL() << "no error";
  } catch (const SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/scene.yaml: expected a readable scene file, found no such file"),
              std::string::npos) << e.what();
  }
}

namespace {
const char* kRod = R"(model: rod
rod:
  length: 1.0
  youngs_modulus: 2.5e8
  poisson_ratio: 0.25
  density: 1500
  section: {type: solid_circle, radius: 0.005}
ends:
  left: {type: pinned}
  right: {type: roller, force: -1.0}
loads:
  F: {type: moving_force, force: 2.0, speed: 1.0}
)";
}  // namespace

// A sprung mass on the rod: accepted alone, on the rod from t = 0, fixed steps; vehicles and axle
// trains stay on the beam.
TEST(Scene, SprungMassOnTheRod) {
  const std::string sprung = "loads.F={type: sprung_mass, mass: 0.1, stiffness: 40, speed: 1.0";
  const Scene s = parse_scene(kRod, "scene.yaml", {sprung + ", start: 0.2}"});
  ASSERT_EQ(s.loads.size(), 1u);
  EXPECT_EQ(s.loads[0].type, LoadType::sprung_mass);
  expect_error({sprung + ", entry_time: 0.1}"}, {"loads.F.entry_time", "0 for a sprung_mass on the rod", "0.1"}, kRod);
  expect_error({sprung + ", start: 1.5}"}, {"loads.F.start", "a position on the structure, in [0, 1]", "1.5"}, kRod);
  expect_error({sprung + "}", "loads.G={type: moving_force, force: 1.0, speed: 1.0}"},
               {"loads.", "a sprung_mass on the rod as the only load", "2 loads"}, kRod);
  expect_error({sprung + "}", "time.adaptive.tolerance=1e-3"}, {"time.adaptive", "fixed steps with a sprung_mass"}, kRod);
  expect_error({"loads.F={type: axle_train, offsets: [0, 2], loads: [1, 1], speed: 1.0}"},
               {"loads.F.type", "vehicles and axle trains ride on the beam model", "'axle_train'"}, kRod);
}

TEST(Scene, RodSceneWithRollerAndDefaults) {
  const Scene s = parse_scene(kRod, "scene.yaml");
  EXPECT_EQ(s.model, Model::Rod);
  EXPECT_NEAR(s.rod.shear_modulus, 1.0e8, 1e-6);
  EXPECT_NEAR(s.rod.section.J, M_PI * std::pow(0.005, 4) / 2, 1e-20);
  EXPECT_EQ(s.left.type, EndType::pinned);
  EXPECT_EQ(s.right.type, EndType::roller);
  EXPECT_DOUBLE_EQ(s.right.axial_force, -1.0);
  EXPECT_EQ(s.initial_state.type, InitialStateType::static_equilibrium);
  EXPECT_DOUBLE_EQ(s.time.dt, 0.01);  // auto: ds / v with 101 nodes and v = 1
  EXPECT_FALSE(s.continuation.enabled);
  ASSERT_EQ(s.loads.size(), 1u);
  EXPECT_EQ(s.loads[0].force, traverse::Vec3(0, -2, 0));
  expect_error({"ends.right.slide_axis=[1, 0, 0]"}, {"ends.right.slide_axis", "perpendicular to the pin axis"}, kRod);
  expect_error({"beam.length=1"}, {"beam: expected no 'beam' here: it applies only with model: beam"}, kRod);
}

TEST(Scene, SolverSectionKeepsTheFilesValuesTypesAndOrder) {
  // The solver section goes to the solver module and its NOX and Stratimikos sublists on to
  // Trilinos as the file gives them: a whole number an int, another number a double,
  // true/false a bool, anything else a string, sublists nested, in the file's order.
  const std::string text = std::string(kRod) + R"(solver:
  Max Newton Iterations: 12
  Residual Tolerance: 1e-9
  Verbose: false
  Line Search: Backtrack
  NOX:
    Line Search:
      Backtrack: {Max Iters: 7, Reduction Factor: 0.5}
    Printing: {Output Precision: 3}
)";
  const Scene s = parse_scene(text, "scene.yaml");
  const Teuchos::ParameterList& p = s.solver_parameters();
  EXPECT_EQ(p.get<int>("Max Newton Iterations"), 12);
  EXPECT_EQ(p.get<double>("Residual Tolerance"), 1e-9);
  EXPECT_EQ(p.get<bool>("Verbose"), false);
  EXPECT_EQ(p.get<std::string>("Line Search"), "Backtrack");
  const auto& backtrack = p.sublist("NOX").sublist("Line Search").sublist("Backtrack");
  EXPECT_EQ(backtrack.get<int>("Max Iters"), 7);
  EXPECT_EQ(backtrack.get<double>("Reduction Factor"), 0.5);
  std::vector<std::string> order;
  for (const auto& e : p) order.push_back(e.first);
  EXPECT_EQ(order, (std::vector<std::string>{"Max Newton Iterations", "Residual Tolerance", "Verbose", "Line Search",
                                             "NOX"}));
  // `traverse check` shows the section so that it reads back the same.
  const Scene again = parse_scene(describe_scene(s), "described.yaml");
  EXPECT_TRUE(Teuchos::haveSameValues(again.solver_parameters(), p));

  EXPECT_TRUE(s.has("solver.NOX.Line Search.Backtrack.Max Iters"));
  EXPECT_TRUE(s.has("loads.F.force"));
  EXPECT_TRUE(s.has("loads.F.entry_time"));  // filled in by its default
  EXPECT_FALSE(s.has("loads.F.mass"));
  EXPECT_FALSE(s.has("loads.G.force"));  // no load G
  EXPECT_FALSE(s.has("mesh.ds"));
  EXPECT_FALSE(s.has("loads.F.force.x"));  // a value, not a section
  const Scene unvalidated;
  EXPECT_FALSE(unvalidated.has("mesh"));
  EXPECT_THROW((void)unvalidated.solver_parameters(), std::logic_error);
}

/// The end conditions come from their one declaration (traverse/core/end_types.hpp):
/// its words in enumerator order, each type in `traverse check --types`, and each parameter
/// read into its member of EndSpec (a direction normalised).
TEST(Scene, EndTypesAreTheirDeclarations) {
  const auto& decl = traverse::end_type_declarations();
  ASSERT_EQ(enum_names<EndType>().size(), decl.size());
  const std::string types = describe_types();
  for (size_t i = 0; i < decl.size(); ++i) {
    EXPECT_EQ(static_cast<size_t>(decl[i].type), i);
    EXPECT_EQ(enum_names<EndType>()[i], decl[i].word);
    EXPECT_NE(types.find(decl[i].doc), std::string::npos) << decl[i].word;
  }
  const Scene s = parse_scene(kRod, "scene.yaml",
                              {"ends.left.type=prescribed", "ends.left.velocity=[0, 2, 0]", "ends.right.axis=[2, 0, 0]",
                               "ends.right.slide_axis=[0, 0, 3]"});
  EXPECT_EQ(s.left.type, EndType::prescribed);
  EXPECT_EQ(s.left.velocity, traverse::Vec3(0, 2, 0));
  EXPECT_EQ(s.left.rotation_rate, traverse::Vec3::Zero());
  EXPECT_EQ(s.right.axis, traverse::Vec3::UnitX());
  EXPECT_EQ(s.right.slide_axis, traverse::Vec3::UnitZ());
  EXPECT_DOUBLE_EQ(s.right.axial_force, -1.0);
  expect_error({"ends.right.axis=[0, 0, 0]"}, {"ends.right.axis: expected a non-zero axis, found [0, 0, 0]"}, kRod);
}

TEST(Scene, InitialStatesAndContinuation) {
  const Scene s = parse_scene(kRod, "scene.yaml",
                              {"initial_state={type: arch, end_to_end: 0.8}", "continuation.parameter=load_position",
                               "continuation.stop=1", "continuation.step=0.01",
                               "continuation.probes={c: {type: end_compression}, y: {type: point, at: 0.5, "
                               "quantity: position, component: y}}"});
  EXPECT_EQ(s.initial_state.type, InitialStateType::arch);
  EXPECT_DOUBLE_EQ(s.initial_state.end_to_end, 0.8);
  ASSERT_TRUE(s.continuation.enabled);
  EXPECT_EQ(s.continuation.method, ContinuationMethod::arclength);
  EXPECT_DOUBLE_EQ(s.continuation.max_step, 0.1);
  ASSERT_EQ(s.continuation.probes.size(), 2u);
  EXPECT_EQ(s.continuation.probes[1].component, 1);
  expect_error({"initial_state.type=arch"}, {"initial_state.end_to_end", "type: arch"}, kRod);
  expect_error({"initial_state={type: arch, end_to_end: 1.5}"}, {"initial_state.end_to_end", "shorter than the rod"}, kRod);
  expect_error({"initial_state.type=file"}, {"initial_state.file", "continuation output file"}, kRod);
  expect_error({"continuation={parameter: load_position, stop: 1}"}, {"continuation.step", "required"}, kRod);
  expect_error({"continuation={parameter: twist, stop: 1, step: 0.1}"}, {"continuation.parameter", "one of {end_load"}, kRod);
  expect_error({"continuation={parameter: load_position, stop: 1, step: 0.1, probes: {p: {type: point, at: 0.5, "
                "quantity: position, component: '2'}}}"},
               {"continuation.probes.p.component", "x, y or z for quantity position"}, kRod);
}

// rod.model and its keys: the default is the inextensible rod; the shear coefficient defaults to
// Cowper's for the section; a key the chosen model does not read is refused, located.
TEST(Scene, RodModelStiffnessesShearCoefficientAndDamping) {
  const Scene s = parse_scene(kRod, "scene.yaml");
  EXPECT_EQ(s.rod.strain, RodStrain::inextensible);
  EXPECT_EQ(s.rod.damping_bending, 0.0);
  const double nu = 0.25, A = M_PI * 0.005 * 0.005, G = 1.0e8;
  const Scene sh = parse_scene(kRod, "scene.yaml", {"rod.model=shearable", "rod.damping={axial: 2, shear: 3, bending: 4}"});
  EXPECT_EQ(sh.rod.strain, RodStrain::shearable);
  EXPECT_NEAR(sh.rod.shear_coefficient, 6.0 * (1.0 + nu) / (7.0 + 6.0 * nu), 1e-12);
  EXPECT_NEAR(sh.rod.axial_stiffness, 2.5e8 * A, 1e-9);
  EXPECT_NEAR(sh.rod.shear_stiffness, sh.rod.shear_coefficient * G * A, 1e-9);
  EXPECT_EQ(sh.rod.damping_axial, 2.0);
  EXPECT_EQ(sh.rod.damping_shear, 3.0);
  EXPECT_EQ(sh.rod.damping_bending, 4.0);
  EXPECT_EQ(sh.rod.damping_torsion, 0.0);
  const Scene rect = parse_scene(kRod, "scene.yaml",
                                 {"rod.model=shearable", "rod.section={type: rectangle, width: 0.01, height: 0.02}"});
  EXPECT_NEAR(rect.rod.shear_coefficient, 10.0 * (1.0 + nu) / (12.0 + 11.0 * nu), 1e-12);
  const Scene tube = parse_scene(kRod, "scene.yaml", {"rod.model=shearable",
                                 "rod.section={type: hollow_circle, outer_radius: 0.01, inner_radius: 0.005}"});
  const double m2 = 0.25, q = (1.0 + m2) * (1.0 + m2);
  EXPECT_NEAR(tube.rod.shear_coefficient, 6.0 * (1.0 + nu) * q / ((7.0 + 6.0 * nu) * q + (20.0 + 12.0 * nu) * m2), 1e-12);
  const Scene given = parse_scene(kRod, "scene.yaml", {"rod.model=shearable", "rod.shear_coefficient=0.5",
                                  "rod.axial_stiffness=1e4", "rod.shear_stiffness=2e3"});
  EXPECT_EQ(given.rod.shear_coefficient, 0.5);
  EXPECT_EQ(given.rod.axial_stiffness, 1e4);
  EXPECT_EQ(given.rod.shear_stiffness, 2e3);
  std::printf("Cowper k: circle %.6f, rectangle %.6f, tube (m = 1/2) %.6f\n", sh.rod.shear_coefficient,
              rect.rod.shear_coefficient, tube.rod.shear_coefficient);

  expect_error({"rod.model=stretchy"}, {"rod.model", "inextensible", "shearable"}, kRod);
  expect_error({"rod.axial_stiffness=1e4"}, {"rod.axial_stiffness", "no axial stiffness for the inextensible rod"}, kRod);
  expect_error({"rod.model=extensible", "rod.shear_coefficient=0.8"}, {"rod.shear_coefficient", "rod.model extensible"},
               kRod);
  expect_error({"rod.model=shearable", "rod.section={type: properties, area: 1e-4, second_moment: 1e-9}"},
               {"rod.shear_coefficient", "given by its properties", "none"}, kRod);
  expect_error({"rod.damping={axial: 1}"}, {"rod.damping.axial", "no axial viscosity"}, kRod);
  expect_error({"rod.model=extensible", "rod.damping={shear: 1}"}, {"rod.damping.shear", "no shear viscosity"}, kRod);
  expect_error({"rod.damping={bending: -1}"}, {"rod.damping.bending"}, kRod);
  EXPECT_NO_THROW(parse_scene(kRod, "scene.yaml", {"rod.damping={bending: 1e-3, torsion: 1e-3}"}));
}
