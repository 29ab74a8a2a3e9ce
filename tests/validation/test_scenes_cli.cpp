// Statics and arch scenes through the traverse executable: a continuation scene finds the
// Euler pitchfork and writes the continuation layout; an arch scene forms the arch and runs
// the dynamics from it; a dynamic scene starts from a state saved by a continuation run.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "traverse/output/continuation_writer.hpp"
#include "traverse/output/reader.hpp"

namespace fs = std::filesystem;

namespace {

using traverse::testing::h5_dataset;
using traverse::testing::run_traverse;

fs::path scratch() { return traverse::testing::scratch_dir("scenes"); }
const fs::path kInputs = traverse::testing::inputs_dir();

}  // namespace

TEST(ScenesCli, EulerBucklingSceneFindsThePitchfork) {
  const std::string out = (scratch() / "euler.h5").string();
  std::string log;
  ASSERT_EQ(run_traverse("run " + (kInputs / "statics" / "euler_buckling.yaml").string() + " -o " + out +
                    " --overwrite --set mesh.ds=0.05",
                &log),
            0)
      << log;
  const auto types = h5_dataset(out, "/bifurcations/end_load");
  ASSERT_GE(types.size(), 1u) << log;
  const double EI = 2.5e8 * M_PI * std::pow(0.005, 4) / 4.0, PE = M_PI * M_PI * EI;
  std::cout << "  pitchfork at P = " << types[0] << " N, pi^2 EI / L^2 = " << PE << " N\n";
  EXPECT_NEAR(types[0], PE, 5e-3 * PE);  // 20 cells: discretisation error ~ 2.6e-3 relative
  const auto unstable = h5_dataset(out, "/continuation/unstable_modes");
  const auto P = h5_dataset(out, "/continuation/end_load");
  const auto branch = h5_dataset(out, "/continuation/branch");
  ASSERT_EQ(P.size(), unstable.size());
  for (size_t i = 0; i < P.size(); ++i) {
    if (branch[i] != 0) continue;
    EXPECT_EQ(unstable[i], P[i] < types[0] ? 0.0 : 1.0) << "P = " << P[i];
  }
  // The switched branch is buckled and stable.
  const auto y = h5_dataset(out, "/continuation/mid_y");
  double lifted = 0.0;
  for (size_t i = 0; i < y.size(); ++i)
    if (branch[i] == 1) lifted = std::max(lifted, std::abs(y[i]));
  EXPECT_GT(lifted, 0.05);
  const auto final_state = traverse::output::read_state(out, "final");
  EXPECT_EQ(final_state.r.size(), 21u * 3u);
}

TEST(ScenesCli, ArchSceneFormsTheArchAndRunsFromIt) {
  const std::string out = (scratch() / "arch.h5").string();
  std::string log;
  ASSERT_EQ(run_traverse("run " + (kInputs / "arch" / "shallow_arch_v2.0.yaml").string() + " -o " + out +
                    " --overwrite --set mesh.ds=0.05 --set time.end=0.05",
                &log),
            0)
      << log;
  traverse::output::Reader f(out);
  EXPECT_NE(f.attribute("initial_state").find("arch formed"), std::string::npos) << f.attribute("initial_state");
  const auto mid = f.probe("midpoint").values;
  // Elastica rise of the shallow arch without gravity: w/L = k/K = 0.2242; gravity lowers it.
  std::cout << "  formed shallow arch: midpoint (" << mid[0] << ", " << mid[1] << ", " << mid[2] << ") m\n";
  EXPECT_NEAR(mid[1], 0.2242, 0.01);
  EXPECT_NEAR(mid[2], 0.864545 / 2, 1e-9);
  EXPECT_NEAR(mid[0], 0.0, 1e-12);
}

// initial_state.loaded: the formed arch solved again with the load at its t = 0 position, so the
// start is in equilibrium with it and its appearance is no step. Undamped, 10 steps while the
// load moves 5 mm. A load starting at the pin weighs on the support alone: both starts are the
// same arch and nothing rings. A load starting at s = 0.25 m: the unloaded start rings (the load
// appears at once), the loaded one hardly moves.
TEST(ScenesCli, LoadedArchStartsInEquilibriumWithTheLoad) {
  const std::string scene = (kInputs / "arch" / "shallow_arch_v0.5.yaml").string();
  const std::string common = " --overwrite -q --set mesh.ds=0.02 --set scheme.rho_inf=1 --set time.end=0.01"
                             " --set time.dt=0.001 --set output.fields=[]";
  for (const char* start : {"0", "0.25"}) {
    double moved[2], spin[2], start_z[2];
    for (int loaded = 0; loaded < 2; ++loaded) {
      const std::string out = (scratch() / ("arch_loaded_" + std::to_string(loaded) + ".h5")).string();
      std::string log;
      ASSERT_EQ(run_traverse("run " + scene + " -o " + out + common + " --set loads.F.start=" + start +
                                 " --set initial_state.loaded=" + (loaded ? "true" : "false"),
                             &log),
                0)
          << log;
      traverse::output::Reader f(out);
      const auto mid = f.probe("midpoint").values, w = f.probe("hinge_spin").values;
      moved[loaded] = spin[loaded] = 0.0;
      for (size_t k = 0; k < mid.size(); k += 3)
        for (int c = 0; c < 3; ++c) {
          moved[loaded] =
              std::max(moved[loaded], std::abs(mid[k + static_cast<size_t>(c)] - mid[static_cast<size_t>(c)]));
          spin[loaded] = std::max(spin[loaded], std::abs(w[k + static_cast<size_t>(c)]));
        }
      start_z[loaded] = mid[2];
    }
    std::cout << "  load starting at " << start << " m: midpoint moved " << moved[0] << " m (unloaded start), "
              << moved[1] << " m (loaded); hinge spin " << spin[0] << ", " << spin[1] << " rad/s; start midpoint z "
              << start_z[0] << ", " << start_z[1] << " m\n";
    if (std::string(start) == "0") {  // the support carries it: the same arch, the same run
      EXPECT_LT(std::abs(start_z[1] - start_z[0]), 1e-12);
      EXPECT_LT(std::abs(moved[1] - moved[0]), 1e-12);
    } else {
      EXPECT_LT(moved[1], 0.2 * moved[0]);
      EXPECT_LT(spin[1], 0.2 * spin[0]);
      EXPECT_GT(std::abs(start_z[1] - start_z[0]), 1e-4);  // the load's static deflection
    }
  }
  // Not with another start, nor without exactly one load on the arch at t = 0: exit 2, the key named.
  std::string log;
  EXPECT_EQ(run_traverse("check " + (kInputs / "default.yaml").string() + " --set initial_state.loaded=true", &log), 2);
  EXPECT_NE(log.find("initial_state.loaded"), std::string::npos) << log;
  EXPECT_EQ(run_traverse("check " + scene + " --set initial_state.loaded=true --set loads.F.entry_time=1", &log), 2);
  EXPECT_NE(log.find("initial_state.loaded"), std::string::npos) << log;
  EXPECT_EQ(run_traverse("check " + (kInputs / "statics" / "shallow_arch_sigma.yaml").string() +
                    " --set initial_state.loaded=true",
                &log),
            2);
  EXPECT_NE(log.find("initial_state.loaded"), std::string::npos) << log;
}

// A load that appears inside the undamped arch at once rings it, and an adaptive run spends its
// steps on the ringing: over the first 0.2 s (the load starting at 0.25 m moves 0.1 m) the
// unloaded start needs several times the steps of the loaded one (docs/adaptive.md, "The load's
// entry"). A load entering at the pin does not ring it: the unloaded start takes no more steps
// than the loaded one of the load inside.
TEST(ScenesCli, LoadedArchStartSparesTheAdaptiveSteps) {
  const std::string scene = (kInputs / "arch" / "shallow_arch_v0.5.yaml").string();
  long steps[3] = {0, 0, 0};
  for (int k = 0; k < 3; ++k) {
    std::string log;
    ASSERT_EQ(run_traverse("run " + scene + " -o " + (scratch() / "arch_adaptive_loaded.h5").string() +
                               " --overwrite --set mesh.ds=0.02 --set scheme.rho_inf=1 --set time.end=0.2 --set "
                               "time.dt=0.01 --set output.fields=[] --set time.adaptive.tolerance=1e-4" +
                               " --set initial_state.loaded=" + (k == 1 ? "true" : "false") +
                               " --set loads.F.start=" + (k == 2 ? "0" : "0.25"),
                           &log),
              0)
        << log;
    const size_t at = log.find("adaptive: ");
    ASSERT_NE(at, std::string::npos) << log;
    steps[k] = std::stol(log.substr(at + 10));
  }
  std::cout << "  adaptive steps to t = 0.2 s, the load from 0.25 m: " << steps[0] << " (unloaded start), " << steps[1]
            << " (loaded); from the pin: " << steps[2] << "\n";
  EXPECT_GT(steps[0], 2 * steps[1]);  // measured 2 128 against 666
  EXPECT_LT(steps[2], 2 * steps[1]);  // 475
}

// A sweep whose cases form the same arch forms it once: the later cases reuse it (root
// attribute initial_state says so) and give the same output, bit for bit, as separate runs.
TEST(ScenesCli, SweepOfArchScenesFormsTheArchOnce) {
  const std::string scene = (kInputs / "arch" / "shallow_arch_v2.0.yaml").string();
  const std::string common = " --set mesh.ds=0.05 --set time.end=0.05 --set output.fields=[]";
  const fs::path dir = scratch() / "arch_sweep";
  std::string log;
  ASSERT_EQ(run_traverse("sweep " + scene + " -o " + dir.string() + " --overwrite -q" + common + " --vary loads.F.speed=1,2",
                &log),
            0)
      << log;
  const std::string first = traverse::output::Reader((dir / "case_0000.h5").string()).attribute("initial_state");
  const std::string second = traverse::output::Reader((dir / "case_0001.h5").string()).attribute("initial_state");
  EXPECT_NE(first.find("arch formed"), std::string::npos) << first;
  EXPECT_EQ(first.find("reused"), std::string::npos) << first;
  EXPECT_NE(second.find("formed earlier in this process, reused"), std::string::npos) << second;
  const std::string alone = (scratch() / "arch_sweep_alone.h5").string();
  ASSERT_EQ(run_traverse("run " + scene + " -o " + alone + " --overwrite -q" + common + " --set loads.F.speed=2", &log), 0)
      << log;
  const auto a = traverse::output::Reader((dir / "case_0001.h5").string()).probe("midpoint").values;
  const auto b = traverse::output::Reader(alone).probe("midpoint").values;
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) EXPECT_EQ(a[k], b[k]) << k;
}

TEST(ScenesCli, DynamicsStartFromAStateSavedByAContinuationRun) {
  const std::string statics = (scratch() / "sag.h5").string();
  std::string log;
  // Gravity raised on the hanging cable by continuation; its final state starts the dynamics.
  ASSERT_EQ(run_traverse("run " + (kInputs / "rod" / "hanging_cable_F2_a0.5.yaml").string() + " -o " + statics +
                    " --overwrite --set mesh.ds=0.05 --set initial_state.type=rest"
                    " --set 'continuation={parameter: gravity_factor, start: 0, stop: 1, step: 0.25, method: natural,"
                    " stability: false}'",
                &log),
            0)
      << log;
  const std::string dyn = (scratch() / "from_file.h5").string();
  ASSERT_EQ(run_traverse("run " + (kInputs / "rod" / "hanging_cable_F2_a0.5.yaml").string() + " -o " + dyn +
                    " --overwrite --set mesh.ds=0.05 --set 'initial_state={type: file, file: " + statics + "}'",
                &log),
            0)
      << log;
  const std::string ref = (scratch() / "static_start.h5").string();
  ASSERT_EQ(run_traverse("run " + (kInputs / "rod" / "hanging_cable_F2_a0.5.yaml").string() + " -o " + ref +
                    " --overwrite --set mesh.ds=0.05 --set loads.F.start=0.0 --set loads.F.entry_time=0.0",
                &log),
            0)
      << log;
  // Same initial sag (the static start also carries the load at s = 0, which goes to the clamp).
  const double a = traverse::output::Reader(dyn).probe("midspan").values[1];
  const double b = traverse::output::Reader(ref).probe("midspan").values[1];
  std::cout << "  initial midspan height from the file " << a << " m, from the static start " << b << " m\n";
  EXPECT_NEAR(a, b, 1e-8);
  // A state with another node count is refused, naming the key.
  ASSERT_EQ(run_traverse("run " + (kInputs / "rod" / "hanging_cable_F2_a0.5.yaml").string() + " -o " +
                    (scratch() / "bad.h5").string() + " --overwrite --set 'initial_state={type: file, file: " + statics + "}'",
                &log),
            2)
      << log;
  EXPECT_NE(log.find("initial_state.file"), std::string::npos) << log;
}
