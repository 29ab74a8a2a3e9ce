// Planar fast path through the traverse executable: the path each scene gets
// (scheme.planar: auto), the output attribute that says so and the motion it allows, planar against
// forced-3D output files on 1 and 2 ranks, and 'on' refused (exit 2, naming the key) for a
// scene that is not planar.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <signal.h>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>

#include "process.hpp"
#include "traverse/output/reader.hpp"

using traverse::testing::scratch;

namespace fs = std::filesystem;
using traverse::output::Reader;

namespace {

const std::string kInputs = std::string(TRAVERSE_SOURCE_DIR) + "/inputs";
const std::string kCable = kInputs + "/default.yaml";
const std::string kDeepArch = kInputs + "/arch/deep_arch_v0.01.yaml";
const std::string kShallowArch = kInputs + "/arch/shallow_arch_v0.5.yaml";
// Every field, so that the comparison covers the whole state.
const std::string kFields = " --set output.fields=[r,R,u,omega,kappa,n,m] -q";

using Result = traverse::testing::RunResult;

Result run(const std::string& prefix, const std::string& args) {
  return traverse::testing::run_command(prefix + std::string(TRAVERSE_EXE) + " " + args);
}

std::string mpirun(int ranks) {
  return ranks == 1 ? "" : std::string(TRAVERSE_MPIEXEC) + " --allow-run-as-root --oversubscribe -n " +
                               std::to_string(ranks) + " ";
}

// The largest |x| (the component along d1, the plane normal (1, 0, 0) of these scenes) of the
// centreline r over every node and output step of a file: 0 on the planar path, where the
// motion is in the plane by construction; the deep arch's lateral trigger moves it out of it.
double largest_out_of_plane(const std::string& file) {
  const Reader r(file);
  double x = 0.0;
  for (std::size_t step = 0; step < r.steps_written(); ++step) {
    const std::vector<double> v = r.field("r", step);
    for (std::size_t k = 0; k < v.size(); k += 3) x = std::max(x, std::abs(v[k]));
  }
  return x;
}

// The linear solver is named so that these tests do not depend on the default choice.
std::string solver(int ranks) {
  return ranks == 1 ? " --set 'solver.Linear Solver=KLU2'" : " --set 'solver.Linear Solver=GMRES'";
}

// The hanging cable (default scene, 21 nodes, `extra` settings) on the planar path (auto) and
// forced 3D with every field: the attribute names the path, the planar run stays in the plane;
// returns the largest output difference between them.
double cable_planar_against_3d(const std::string& name, int ranks, const std::string& extra) {
  const fs::path d = scratch(name + "_np" + std::to_string(ranks));
  const std::string a = (d / "auto.h5").string(), b = (d / "off.h5").string();
  const std::string common = " --set mesh.ds=0.05" + solver(ranks) + kFields + extra;
  const Result ra = run(mpirun(ranks), "run " + kCable + " -o " + a + common);
  EXPECT_EQ(ra.code, 0) << ra.out;
  const Result rb = run(mpirun(ranks), "run " + kCable + " -o " + b + common + " --set scheme.planar=off");
  EXPECT_EQ(rb.code, 0) << rb.out;
  if (ra.code != 0 || rb.code != 0) return HUGE_VAL;
  EXPECT_EQ(Reader(a).attribute("rod_path"), "planar");
  EXPECT_EQ(Reader(b).attribute("rod_path"), "3D");
  EXPECT_EQ(largest_out_of_plane(a), 0.0);
  std::string why;
  const double diff = traverse::testing::max_file_difference(a, b, why);
  std::printf("  %s, %d rank(s): planar vs 3D output max |difference| %.2e (%s); %s\n", name.c_str(), ranks, diff,
              why.c_str(), Reader(a).attribute("rod_path_detail").c_str());
  return diff;
}

// The cable: same output to 1e-10, on 1 and 2 ranks.
TEST(PlanarCli, CablePlanarEquals3D) {
  for (int ranks : {1, 2}) EXPECT_LE(cable_planar_against_3d("planar_cable", ranks, ""), 1e-10);
}

// The rods that strain and the viscosities on the planar path (docs/rod.md): the cable made
// shearable and damped, from its static equilibrium (the static kernels' compliance): the same
// output to 1e-10, on 1 and 2 ranks; and with a carried spatial history (rho_inf_space 0.8),
// where the bending viscosity reads the carried kappa_s's rate.
TEST(PlanarCli, ShearableDampedCablePlanarEquals3D) {
  const std::string strain = " --set rod.model=shearable --set 'rod.damping={axial: 5, shear: 5, bending: 1.0e-5, "
                             "torsion: 1.0e-5}' --set output.fields=[r,R,u,omega,kappa,n,m,v]";
  for (int ranks : {1, 2}) EXPECT_LE(cable_planar_against_3d("planar_shearable", ranks, strain), 1e-10);
  for (int ranks : {1, 2})
    EXPECT_LE(cable_planar_against_3d("planar_shearable_carried", ranks, strain + " --set scheme.rho_inf_space=0.8"),
              1e-10);
}

// The arches: the shallow arch is planar (and equal to its 3D run), the deep arch with its
// lateral trigger runs in 3D and says why. Two time steps each at ds = 0.05.
TEST(PlanarCli, ArchPaths) {
  const fs::path d = scratch("planar_arches");
  const std::string sa = (d / "shallow.h5").string(), sb = (d / "shallow_off.h5").string();
  const std::string shallow = " --set mesh.ds=0.05 --set time.end=0.2" + solver(1) + kFields;
  const Result r1 = run("", "run " + kShallowArch + " -o " + sa + shallow);
  ASSERT_EQ(r1.code, 0) << r1.out;
  const Result r2 = run("", "run " + kShallowArch + " -o " + sb + shallow + " --set scheme.planar=off");
  ASSERT_EQ(r2.code, 0) << r2.out;
  EXPECT_EQ(Reader(sa).attribute("rod_path"), "planar");
  std::string why;
  const double diff = traverse::testing::max_file_difference(sa, sb, why);
  std::printf("  shallow arch: %s; planar vs 3D max |difference| %.2e (%s)\n",
              Reader(sa).attribute("rod_path_detail").c_str(), diff, why.c_str());
  EXPECT_LE(diff, 1e-10) << why;

  const std::string da = (d / "deep.h5").string();
  const Result r3 = run("", "run " + kDeepArch + " -o " + da +
                                " --set mesh.ds=0.05 --set time.end=10 --set output.fields=[r]" + solver(1) + " -q");
  ASSERT_EQ(r3.code, 0) << r3.out;
  const std::string detail = Reader(da).attribute("rod_path_detail");
  const double lateral = largest_out_of_plane(da);
  std::printf("  deep arch: %s; largest |x| of the centreline %.3e m\n", detail.c_str(), lateral);
  EXPECT_EQ(Reader(da).attribute("rod_path"), "3D");
  // The lateral trigger (a force component along d1) moves the arch out of its plane, which
  // the planar path could not represent.
  EXPECT_GT(lateral, 0.0);
}

// A killed planar run restarts on the planar path (the path is stored with the restart
// point) and ends bit for bit equal to the uninterrupted run; restarted with
// scheme.planar=off it continues on the 3D path, equal to 1e-10.
TEST(PlanarCli, RestartKeepsThePath) {
  using namespace traverse::testing;
  const fs::path d = scratch("planar_restart");
  const std::string ref = (d / "reference.h5").string();
  const std::string args = " --set mesh.ds=0.02 --restart-interval 0" + solver(1) + kFields;
  ASSERT_EQ(run("", "run " + kCable + " -o " + ref + args).code, 0);
  for (const std::string mode : {"", " --set scheme.planar=off"}) {
    const std::string out = (d / (mode.empty() ? "run.h5" : "run_off.h5")).string();
    const Child c = spawn(split_args(std::string(TRAVERSE_EXE) + " run " + kCable + " -o " + out + args),
                          (d / "stopped.log").string());
    ASSERT_TRUE(wait_for_steps(c, out, 5)) << read_text((d / "stopped.log").string());
    kill(c.pid, SIGKILL);
    ASSERT_EQ(wait_exit(c), 128 + SIGKILL);
    const long kept = static_cast<long>(Reader(out).steps_written());
    const Result r = run("", "run --restart " + out + mode);
    ASSERT_EQ(r.code, 0) << r.out;
    std::string why;
    const double diff = max_file_difference(ref, out, why);
    const std::string detail = Reader(out).attribute("rod_path_detail");
    std::printf("  killed after %ld of 51 output steps, restarted%s: %s; vs uninterrupted max |difference| %.2e\n",
                kept, mode.c_str(), detail.c_str(), diff);
    EXPECT_LT(kept, 51);
    if (mode.empty()) {
      EXPECT_EQ(diff, 0.0) << why;
      EXPECT_EQ(Reader(out).attribute("rod_path"), "planar");
    } else {
      EXPECT_LE(diff, 1e-10) << why;
      EXPECT_EQ(Reader(out).attribute("rod_path"), "3D");
    }
  }
}

// scheme.planar: on for a scene that is not planar: exit 2 before anything is computed, the
// message names the key and the reason, no output file.
TEST(PlanarCli, OnRefusesANonPlanarScene) {
  const fs::path d = scratch("planar_on");
  const std::string out = (d / "deep.h5").string();
  for (const std::string& cmd : {"check " + kDeepArch + " --set scheme.planar=on",
                                "run " + kDeepArch + " --set scheme.planar=on -o " + out,
                                "run " + kCable + " --set scheme.planar=on --set ends.right.axis=[0.6,0,0.8] -o " + out}) {
    const Result r = run("", cmd);
    std::printf("  %s\n    -> exit %d: %s", cmd.substr(0, cmd.find(' ')).c_str(), r.code, r.out.c_str());
    EXPECT_EQ(r.code, 2) << r.out;
    EXPECT_NE(r.out.find("scheme.planar"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("not planar"), std::string::npos) << r.out;
    EXPECT_FALSE(fs::exists(out));
  }
  // 'on' for the planar cable is accepted.
  const Result ok = run("", "check " + kCable + " --set scheme.planar=on");
  EXPECT_EQ(ok.code, 0) << ok.out;
}

// The coupled mass (docs/rod.md "Coupled mass") on both paths, 1 and 2 ranks, the default and
// other linear solvers: the zip line's trolley (ds = 0.05, to t = 0.8 s, released at s = 0.15 m, sliding
// past midspan, where 2 ranks split the rod) gives the same file to 1e-10 in every case.
TEST(PlanarCli, CoupledMassOnBothPathsAndRanks) {
  const fs::path d = scratch("planar_coupled");
  const std::string scene = kInputs + "/rod/coupled_zip_line.yaml";
  const std::string common = " --set mesh.ds=0.05 --set time.end=0.8 --set output.fields=[r,R,u,omega,kappa,n,m]";
  const std::string ref = (d / "planar.h5").string();
  const Result r0 = run("", "run " + scene + " -o " + ref + common);
  ASSERT_EQ(r0.code, 0) << r0.out;
  EXPECT_EQ(Reader(ref).attribute("rod_path"), "planar");
  EXPECT_EQ(largest_out_of_plane(ref), 0.0);
  const auto sigma = Reader(ref).probe("trolley_position").values;
  EXPECT_LT(sigma.front(), 0.5);
  EXPECT_GT(sigma.back(), 0.55);  // crossed into the second rank's nodes
  struct Case {
    int ranks;
    std::string options, path;
  };
  const Case cases[] = {{1, " --set scheme.planar=off", "3D"},
                        {1, " --set scheme.planar=on --set 'solver.Linear Solver=KLU2'", "planar"},
                        {2, "", "planar"},
                        {2, " --set scheme.planar=off --set 'solver.Linear Solver=GMRES'", "3D"}};
  int k = 0;
  for (const Case& c : cases) {
    const std::string out = (d / ("case" + std::to_string(k++) + ".h5")).string();
    const Result r = run(mpirun(c.ranks), "run " + scene + " -o " + out + common + c.options + " -q");
    ASSERT_EQ(r.code, 0) << r.out;
    EXPECT_EQ(Reader(out).attribute("rod_path"), c.path);
    std::string why;
    const double diff = traverse::testing::max_file_difference(ref, out, why);
    std::printf("  coupled trolley, %d rank(s)%s: against 1 rank planar max |difference| %.2e (%s)\n", c.ranks,
                c.options.c_str(), diff, why.c_str());
    EXPECT_LE(diff, 1e-10) << why;
  }
}

}  // namespace
