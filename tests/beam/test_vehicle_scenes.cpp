// The scene keys of vehicles, axle trains, beam damping and the acceleration probe: what they
// read into, and the messages for bad values (file, key, what was expected).
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "traverse/scene/scene.hpp"

using namespace traverse::scene;

namespace {
const std::string kBeam = R"(model: beam
beam:
  length: 25.0
  youngs_modulus: 3.5e10
  density: 2500
  section: {type: properties, area: 7.3432, second_moment: 1.3901}
  supports: simply-supported
  modes: 4
time: {dt: 1.0e-3}
)";

Scene parse(const std::string& extra, const std::vector<std::string>& set = {}) {
  return parse_scene(kBeam + extra, "bridge.yaml", set);
}

// The message of the SceneError a scene raises ("" if it parses).
std::string error_of(const std::string& extra, const std::vector<std::string>& set) {
  try {
    parse(extra, set);
  } catch (const SceneError& e) {
    return e.what();
  }
  return "";
}

void expect_error(const std::string& extra, const std::string& key, const std::string& expected,
                  const std::vector<std::string>& set = {}) {
  const std::string m = error_of(extra, set);
  EXPECT_NE(m.find("bridge.yaml"), std::string::npos) << m;
  EXPECT_NE(m.find(key), std::string::npos) << m;
  EXPECT_NE(m.find("expected " + expected), std::string::npos) << m;
}
}  // namespace

TEST(VehicleScenes, SprungMassAndVehicleAreRead) {
  const Scene s = parse(R"(loads:
  a: {type: sprung_mass, mass: 5750, stiffness: 1.595e6, damping: 100, wheel_mass: 30, speed: 25, contact: unilateral}
  b: {type: vehicle, mass: 5000, pitch_inertia: 2e4, axle_offsets: [1.5, -2.5], stiffness: [1e6, 2e6], speed: 20,
      wheel_masses: [50]}
)");
  ASSERT_EQ(s.loads.size(), 2u);
  const MovingLoadSpec& a = s.loads[0];
  EXPECT_EQ(a.type, LoadType::sprung_mass);
  EXPECT_EQ(a.contact, Contact::unilateral);
  EXPECT_EQ(a.axle_stiffness, std::vector<double>{1.595e6});
  EXPECT_EQ(a.wheel_masses, std::vector<double>{30.0});
  EXPECT_DOUBLE_EQ(a.force.y(), -(5750 + 30) * s.gravity);
  const MovingLoadSpec& b = s.loads[1];
  EXPECT_EQ(b.axle_damping, (std::vector<double>{0.0, 0.0}));
  EXPECT_EQ(b.wheel_masses, (std::vector<double>{50.0, 50.0}));
  EXPECT_DOUBLE_EQ(b.extent(), 4.0);
  // time.end auto: when the trailing axle (4 m behind) leaves, (25 + 4) / 20 s.
  EXPECT_DOUBLE_EQ(b.exit_time(25.0), 29.0 / 20.0);
}

TEST(VehicleScenes, TrainGeneratorLaysOutBogies) {
  const Scene s = parse(R"(loads:
  t: {type: axle_train, speed: 50, generator: {coaches: 2, coach_length: 18, bogie_axle_spacing: 2.5, axle_load: 1.7e5}}
)");
  const MovingLoadSpec& t = s.loads[0];
  // N + 3 = 5 bogies 18 m apart, two axles 2.5 m apart each.
  EXPECT_EQ(t.train_offsets, (std::vector<double>{0, 2.5, 18, 20.5, 36, 38.5, 54, 56.5, 72, 74.5}));
  EXPECT_EQ(t.train_loads, std::vector<double>(10, 1.7e5));
  EXPECT_DOUBLE_EQ(t.exit_time(25.0), (25.0 + 74.5) / 50.0);
}

TEST(VehicleScenes, DampingAndAccelerationProbe) {
  Scene s = parse("output: {probes: {deck: {type: acceleration, at: 12.5}}}\n", {"beam.damping={ratio: 0.02}", "time.end=1"});
  EXPECT_EQ(s.output.probes[0].type, ProbeType::acceleration);
  EXPECT_EQ(s.beam.damping, BeamSpec::Damping::ratios);
  EXPECT_EQ(s.beam.damping_ratios, std::vector<double>{0.02});
  s = parse_scene(kBeam, "bridge.yaml", {"beam.damping={mass: 0.1, stiffness: 1e-4}", "time.end=1"});
  EXPECT_EQ(s.beam.damping, BeamSpec::Damping::rayleigh);
  EXPECT_DOUBLE_EQ(s.beam.rayleigh_stiffness, 1e-4);
}

TEST(VehicleScenes, BadValuesNameTheKeyAndTheExpectation) {
  expect_error("loads: {a: {type: sprung_mass, mass: 1, stiffness: 0, speed: 1}}", "loads.a.stiffness",
               "a finite real number > 0");
  expect_error("loads: {a: {type: sprung_mass, mass: 1, stiffness: 1, speed: 0}}", "loads.a.speed",
               "a sprung mass that moves");
  expect_error("loads: {b: {type: vehicle, mass: 1, pitch_inertia: 1, axle_offsets: [1, -1], stiffness: [1, 2, 3], "
               "speed: 1}}", "loads.b.stiffness", "one value (for every axle) or one per axle");
  expect_error("loads: {b: {type: vehicle, mass: 1, pitch_inertia: 1, axle_offsets: [1], stiffness: [1], speed: 1}}",
               "loads.b.axle_offsets", "at least 2 axles");
  expect_error("loads: {t: {type: axle_train, speed: 1, offsets: [1, 2], loads: [1]}}", "loads.t.offsets",
               "a list starting at 0");
  expect_error("loads: {t: {type: axle_train, speed: 1}}", "loads.t.offsets", "either offsets and loads, or generator");
  expect_error("loads: {t: {type: axle_train, speed: 1, generator: {coaches: 2, coach_length: 3, bogie_axle_spacing: 3, "
               "axle_load: 1}}}", "loads.t.generator.bogie_axle_spacing", "less than coach_length");
  expect_error("", "beam.damping.ratios", "one ratio per mode", {"beam.damping={ratios: [0.1, 0.2]}"});
  expect_error("", "beam.damping", "exactly one of 'ratio', 'ratios'", {"beam.damping={ratio: 0.1, mass: 1}"});
  expect_error("", "beam.damping.ratio", "a finite real number in [0, 1)", {"beam.damping={ratio: 1.5}"});
  expect_error("loads: {a: {type: sprung_mass, mass: 1, stiffness: 1, speed: 1}, f: {type: moving_force, force: 1, "
               "speed: 1}}", "loads.", "only sprung_mass and vehicle loads");
  expect_error("output: {probes: {deck: {type: acceleration, at: 30}}}", "output.probes.deck.at",
               "a position on the structure");
}
