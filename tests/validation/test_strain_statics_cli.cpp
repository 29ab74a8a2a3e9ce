// Statics and static starts of extensible and shearable rods through the traverse executable:
// - the pinned-roller column of inputs/statics/euler_buckling.yaml buckles where the linearised
//   strained rod says: with v = e3 + C n and the end load P, the straight state has n = -P e3
//   and bending about it gives EI theta'' + P (1 - P / EA + P / kGA) theta = 0, so the
//   pitchfork is at P (1 - P / EA + P / kGA) = P_E = pi^2 EI / L^2 (the extensible rod: no
//   shear term; the shear term alone is Haringx's column). Continuation locates it at order 2
//   in ds.
// - EA and kGA times 1e8 reproduce the inextensible rod's pitchfork, and the shipped shallow
//   and deep arches (formed with strain, then crossed by their loads), to 1e-6 relative.
// - A formed arch and a state saved by a continuation run of a strained rod are equilibria of
//   the strained dynamics: started with no load, they stay at rest.
#include <gtest/gtest.h>
#include <hdf5.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <string>
#include <vector>

#include "cli_support.hpp"

namespace fs = std::filesystem;

namespace {

using traverse::testing::h5_dataset;
using traverse::testing::run_traverse;

fs::path scratch() { return traverse::testing::scratch_dir("strain_statics"); }
const fs::path kInputs = traverse::testing::inputs_dir();

// The scene rod: E = 2.5e8 Pa, solid circle r = 0.005 m, L = 1 m.
const double kEI = 2.5e8 * M_PI * std::pow(0.005, 4) / 4.0;
const double kEA = 2.5e8 * M_PI * 0.005 * 0.005;
const double kPE = M_PI * M_PI * kEI;

/// The pitchfork of the strained column: P (1 + a P) = P_E with a = 1 / kGA - 1 / EA.
double strained_pitchfork(double EA, double kGA) {
  const double a = 1.0 / kGA - 1.0 / EA;
  return std::abs(a) < 1e-300 ? kPE : (-1.0 + std::sqrt(1.0 + 4.0 * a * kPE)) / (2.0 * a);
}

/// The first pitchfork the continuation of the Euler scene locates with `sets`.
double pitchfork(const std::string& name, const std::string& sets) {
  const std::string out = (scratch() / (name + ".h5")).string();
  std::string log;
  EXPECT_EQ(run_traverse("run " + (kInputs / "statics" / "euler_buckling.yaml").string() + " -o " + out + " --overwrite -q " + sets,
                &log),
            0)
      << log;
  const auto P = h5_dataset(out, "/bifurcations/end_load");
  EXPECT_GE(P.size(), 1u) << log;
  return P.empty() ? NAN : P[0];
}

std::string number(double x) {
  char b[40];
  std::snprintf(b, sizeof b, "%.17g", x);
  return b;
}

/// The largest difference of two datasets relative to the first's largest magnitude.
double relative_difference(const std::string& a, const std::string& b, const std::string& name) {
  const auto x = h5_dataset(a, name), y = h5_dataset(b, name);
  EXPECT_EQ(x.size(), y.size()) << name;
  double diff = 0.0, scale = 0.0;
  for (size_t i = 0; i < std::min(x.size(), y.size()); ++i) {
    diff = std::max(diff, std::abs(x[i] - y[i]));
    scale = std::max(scale, std::abs(x[i]));
  }
  return diff / scale;
}

/// The largest |u| and |omega| over a run's output steps.
double largest_motion(const std::string& file) {
  double m = 0.0;
  for (const char* f : {"/fields/u", "/fields/omega"})
    for (double v : h5_dataset(file, f)) m = std::max(m, std::abs(v));
  return m;
}

}  // namespace

TEST(StrainStatics, StrainedColumnBucklesAtTheClosedFormAtOrderTwo) {
  struct Model {
    const char* name;
    double EA, kGA;
    std::string sets;
  };
  // Stiffnesses of the order of P_E so that strain moves the pitchfork by 10 %: EA = 10 P_E.
  const double EA = 10.0 * kPE;
  const std::vector<Model> models = {
      {"extensible", EA, INFINITY, "--set rod.model=extensible --set rod.axial_stiffness=" + number(EA)},
      {"shear", 1e6 * EA, EA,
       "--set rod.model=shearable --set rod.axial_stiffness=" + number(1e6 * EA) + " --set rod.shear_stiffness=" + number(EA)},
      {"both", EA, 2.0 * EA,
       "--set rod.model=shearable --set rod.axial_stiffness=" + number(EA) + " --set rod.shear_stiffness=" + number(2.0 * EA)},
  };
  for (const Model& m : models) {
    const double exact = strained_pitchfork(m.EA, m.kGA);
    std::vector<double> err;
    for (double ds : {0.04, 0.02, 0.01}) {
      const double P = pitchfork(std::string(m.name) + "_" + number(ds), m.sets + " --set mesh.ds=" + number(ds));
      err.push_back(std::abs(P / exact - 1.0));
      std::printf("  %-10s ds = %.2f: pitchfork %.8f N, closed form %.8f N (P_E %.8f N), error %.2e\n", m.name, ds, P,
                  exact, kPE, err.back());
    }
    // The strain moves the pitchfork by far more than the discretisation error.
    EXPECT_GT(std::abs(exact / kPE - 1.0), 50.0 * err.back()) << m.name;
    for (size_t i = 0; i + 1 < err.size(); ++i) {
      const double order = std::log2(err[i] / err[i + 1]);
      std::printf("  %-10s order %.2f\n", m.name, order);
      EXPECT_NEAR(order, 2.0, 0.3) << m.name;
    }
    EXPECT_LT(err.back(), 5e-4) << m.name;
  }
}

TEST(StrainStatics, TwoRanksLocateThePitchforkOfOne) {
  const std::string sets = "--set rod.model=shearable --set rod.axial_stiffness=" + number(10.0 * kPE) +
                           " --set rod.shear_stiffness=" + number(20.0 * kPE) + " --set mesh.ds=0.02";
  const double one = pitchfork("ranks1", sets);
  const std::string out = (scratch() / "ranks2.h5").string();
  std::string log;
  ASSERT_EQ(traverse::testing::run_command(std::string(TRAVERSE_MPIEXEC) + " --allow-run-as-root --oversubscribe -n 2 " +
                                           TRAVERSE_EXE + " run " + (kInputs / "statics" / "euler_buckling.yaml").string() +
                                           " -o " + out + " --overwrite -q " + sets)
                .code,
            0);
  const auto two = h5_dataset(out, "/bifurcations/end_load");
  ASSERT_GE(two.size(), 1u);
  // Round-off of the distributed solves moves the continuation's points (61 against 63 here), so
  // the pitchfork is located from other brackets: it agrees to the location's tolerance (its
  // eigenvalue 1e-5 of the bracketing ones: about 1e-5 of a step of 0.05 N).
  std::printf("  shearable pitchfork: 1 rank %.12f N, 2 ranks %.12f N\n", one, two[0]);
  EXPECT_NEAR(two[0] / one, 1.0, 1e-6);
  // The buckled branch's last point, at the same load (the continuation's end, P = 2 N).
  const auto y1 = h5_dataset((scratch() / "ranks1.h5").string(), "/continuation/mid_y"), y2 = h5_dataset(out, "/continuation/mid_y");
  const auto p1 = h5_dataset((scratch() / "ranks1.h5").string(), "/continuation/end_load"), p2 = h5_dataset(out, "/continuation/end_load");
  ASSERT_EQ(p1.back(), 2.0);
  ASSERT_EQ(p2.back(), 2.0);
  std::printf("  buckled at P = 2 N: midspan y %.12f m (1 rank), %.12f m (2 ranks)\n", y1.back(), y2.back());
  EXPECT_NEAR(y2.back(), y1.back(), 1e-10);
}

TEST(StrainStatics, StiffStrainIsTheInextensibleRod) {
  const std::string stiff = "--set rod.model=shearable --set rod.axial_stiffness=" + number(1e8 * kEA) +
                            " --set rod.shear_stiffness=" + number(0.4 * 1e8 * kEA);
  const double inextensible = pitchfork("inextensible", "--set mesh.ds=0.02");
  const double strained = pitchfork("stiff", stiff + " --set mesh.ds=0.02");
  std::printf("  pitchfork: inextensible %.12f N, E A and k G A x 1e8 %.12f N\n", inextensible, strained);
  EXPECT_NEAR(strained / inextensible, 1.0, 1e-6);
  // The shipped arches, formed and crossed (shortened runs).
  struct Arch {
    const char* file;
    const char* sets;
    std::vector<std::string> datasets;
  };
  const std::vector<Arch> arches = {
      {"shallow_arch_v2.0.yaml", "--set time.end=0.25", {"/probes/midpoint", "/probes/end_tangent", "/fields/r", "/fields/n"}},
      {"deep_arch_v0.01.yaml", "--set time.end=2", {"/probes/midpoint", "/fields/r"}},
  };
  for (const Arch& a : arches) {
    const std::string scene = (kInputs / "arch" / a.file).string();
    const std::string ref = (scratch() / (std::string(a.file) + ".h5")).string();
    const std::string str = (scratch() / (std::string(a.file) + ".strained.h5")).string();
    std::string log;
    ASSERT_EQ(run_traverse("run " + scene + " -o " + ref + " --overwrite -q " + a.sets, &log), 0) << log;
    ASSERT_EQ(run_traverse("run " + scene + " -o " + str + " --overwrite -q " + a.sets + " " + stiff, &log), 0) << log;
    for (const auto& name : a.datasets) {
      const double d = relative_difference(ref, str, name);
      std::printf("  %s %s: relative difference %.2e\n", a.file, name.c_str(), d);
      EXPECT_LT(d, 1e-6) << a.file << " " << name;
    }
  }
}

TEST(StrainStatics, StrainedArchAndSavedStatesStartAtRest) {
  // The shallow arch's rod, shearable with the solid section's E A and k G A, formed with strain
  // and started with no load: its end-to-end distance is the one asked for and it stays at rest.
  const std::string scene = (scratch() / "arch_rest.yaml").string();
  {
    std::ofstream f(scene);
    f << "model: rod\ngravity: 9.8\nrod:\n  length: 1.0\n  youngs_modulus: 2.5e8\n  poisson_ratio: 0.25\n"
         "  density: 1500\n  section: {type: solid_circle, radius: 0.005}\n  model: shearable\n"
         "ends:\n  left: {type: pinned, axis: [1, 0, 0]}\n  right: {type: pinned, axis: [1, 0, 0]}\n"
         "mesh:\n  ds: 0.01\ninitial_state:\n  type: arch\n  end_to_end: 0.864545\n"
         "time: {dt: 1.0e-3, end: 0.05}\noutput:\n  fields: [r, u, omega]\n";
  }
  const std::string arch = (scratch() / "arch_rest.h5").string();
  std::string log;
  ASSERT_EQ(run_traverse("run " + scene + " -o " + arch + " --overwrite -q", &log), 0) << log;
  hsize_t steps = 0;
  const auto r = h5_dataset(arch, "/fields/r", &steps);
  const size_t nodes = r.size() / steps / 3;
  const double dz = r[3 * (nodes - 1) + 2] - r[2];
  std::printf("  formed shearable arch: end-to-end %.9f m; largest |u|, |omega| over %llu steps %.2e\n", dz,
              static_cast<unsigned long long>(steps), largest_motion(arch));
  EXPECT_NEAR(dz, 0.864545, 1e-9);
  EXPECT_LT(largest_motion(arch), 1e-10);

  // The post-buckled extensible column saved by a continuation run to P = 1.6 N (the buckled
  // branch's last state), started under that end load: at rest. The same state in the
  // inextensible rod is no equilibrium (its moment balance lacks the stretch), and moves.
  const double EA = 10.0 * kPE;
  const std::string saved = (scratch() / "column_saved.h5").string();
  ASSERT_EQ(run_traverse("run " + (kInputs / "statics" / "euler_buckling.yaml").string() + " -o " + saved +
                    " --overwrite -q --set rod.model=extensible --set rod.axial_stiffness=" + number(EA) +
                    " --set continuation.stop=1.6",
                &log),
            0)
      << log;
  const auto branch = h5_dataset(saved, "/continuation/branch");
  const auto mid = h5_dataset(saved, "/continuation/mid_y");
  const auto load = h5_dataset(saved, "/continuation/end_load");
  ASSERT_FALSE(branch.empty());
  ASSERT_EQ(branch.back(), 1.0) << "the last point is on the buckled branch";
  ASSERT_NEAR(load.back(), 1.6, 1e-12);
  EXPECT_GT(std::abs(mid.back()), 0.1) << "the saved state is buckled";
  auto start = [&](const std::string& name, const std::string& model) {
    const std::string column = (scratch() / (name + ".yaml")).string();
    {
      std::ofstream f(column);
      f << "model: rod\ngravity: 0.0\nrod:\n  length: 1.0\n  youngs_modulus: 2.5e8\n  poisson_ratio: 0.25\n"
           "  density: 1500\n  section: {type: solid_circle, radius: 0.005}\n"
        << model
        << "ends:\n  left: {type: pinned, axis: [1, 0, 0]}\n"
           "  right: {type: roller, axis: [1, 0, 0], slide_axis: [0, 0, 1], force: -1.6}\n"
           "mesh:\n  ds: 0.02\ninitial_state: {type: file, file: "
        << saved << ", state: branch_1_final}\ntime: {dt: 1.0e-3, end: 0.05}\noutput:\n  fields: [u, omega]\n";
    }
    const std::string started = (scratch() / (name + ".h5")).string();
    EXPECT_EQ(run_traverse("run " + column + " -o " + started + " --overwrite -q", &log), 0) << log;
    return largest_motion(started);
  };
  const double strained = start("column_rest", "  model: extensible\n  axial_stiffness: " + number(EA) + "\n");
  const double rigid = start("column_inextensible", "");
  std::printf("  saved buckled extensible column under 1.6 N: largest |u|, |omega| %.2e (in the inextensible rod %.2e)\n",
              strained, rigid);
  EXPECT_LT(strained, 1e-10);
  EXPECT_GT(rigid, 1e-3);
}
