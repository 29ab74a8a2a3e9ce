// Continuation files: points, bifurcations and states written by rank 0, read back.
#include <gtest/gtest.h>
#include <hdf5.h>
#include <mpi.h>

#include <filesystem>

#include "traverse/output/continuation_writer.hpp"
#include "traverse/output/output_error.hpp"

using namespace traverse::output;
namespace fs = std::filesystem;

namespace {

std::string scratch(const std::string& name) {
  const fs::path d = fs::path(TRAVERSE_BINARY_DIR) / "tests" / "output" / "scratch";
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  int size = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const std::string p = (d / (name + "_np" + std::to_string(size) + ".h5")).string();
  if (rank == 0) {
    fs::create_directories(d);
    fs::remove(p);
  }
  MPI_Barrier(MPI_COMM_WORLD);
  return p;
}

NodalState state(int nodes, double offset) {
  NodalState s;
  for (int j = 0; j < nodes; ++j) {
    for (int c = 0; c < 3; ++c) {
      s.r.push_back(offset + j + 0.1 * c);
      s.kappa.push_back(offset - j);
      s.n.push_back(offset * j + c);
    }
    for (int c = 0; c < 9; ++c) s.R.push_back(c % 4 == 0 ? 1.0 : 0.0);
  }
  return s;
}

std::vector<double> read_series(const std::string& path, const std::string& name) {
  const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const hid_t sp = H5Dget_space(d);
  hsize_t n = 0;
  H5Sget_simple_extent_dims(sp, &n, nullptr);
  std::vector<double> v(n);
  if (n) H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  H5Sclose(sp);
  H5Dclose(d);
  H5Fclose(f);
  return v;
}

}  // namespace

TEST(ContinuationWriter, PointsBifurcationsAndStatesReadBack) {
  const std::string path = scratch("continuation");
  const std::vector<double> s{0.0, 0.5, 1.0};
  {
    ContinuationWriter w(MPI_COMM_WORLD, path, false, RunInfo{"0", "cmd", "model: rod", "x.yaml", "rod"}, s,
                         "load_position", "m", {"end_compression", "mid_x"}, {"N", "m"});
    for (int k = 0; k < 5; ++k) w.add_point(k < 3 ? 0 : 1, 0.1 * k, {10.0 + k, -0.01 * k}, k < 2 ? 0 : 1, 1.0 - k);
    w.add_bifurcation("fold", 0, true, 0.15, {11.5, -0.015}, state(3, 1.0));
    w.write_state("final", state(3, 2.0));
    EXPECT_EQ(w.points_written(), 5u);
    w.finish();
  }
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    EXPECT_EQ(read_series(path, "/continuation/load_position"), (std::vector<double>{0.0, 0.1, 0.2, 0.30000000000000004, 0.4}));
    EXPECT_EQ(read_series(path, "/continuation/end_compression"), (std::vector<double>{10, 11, 12, 13, 14}));
    EXPECT_EQ(read_series(path, "/continuation/unstable_modes"), (std::vector<double>{0, 0, 1, 1, 1}));
    EXPECT_EQ(read_series(path, "/continuation/branch"), (std::vector<double>{0, 0, 0, 1, 1}));
    EXPECT_EQ(read_series(path, "/bifurcations/load_position"), (std::vector<double>{0.15}));
    const NodalState f = read_state(path, "final");
    const NodalState expected = state(3, 2.0);
    EXPECT_EQ(f.r, expected.r);
    EXPECT_EQ(f.R, expected.R);
    EXPECT_EQ(f.kappa, expected.kappa);
    EXPECT_EQ(f.n, expected.n);
    EXPECT_THROW(read_state(path, "initial"), OutputError);
  }
}

TEST(ContinuationWriter, RefusesToOverwriteAndMarksAnUnfinishedFile) {
  const std::string path = scratch("continuation_refuse");
  const RunInfo info{"0", "cmd", "", "", "rod"};
  { ContinuationWriter w(MPI_COMM_WORLD, path, false, info, {0.0, 1.0}, "gravity_factor", "1", {}, {}); }
  EXPECT_THROW(ContinuationWriter(MPI_COMM_WORLD, path, false, info, {0.0, 1.0}, "gravity_factor", "1", {}, {}),
               OutputError);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0) {
    const hid_t f = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
    const hid_t a = H5Aopen(f, "status", H5P_DEFAULT);
    const hid_t t = H5Aget_type(a);
    char* value = nullptr;
    H5Aread(a, t, &value);
    EXPECT_EQ(std::string(value).rfind("failed", 0), 0u) << value;
    H5free_memory(value);
    H5Tclose(t);
    H5Aclose(a);
    H5Fclose(f);
  }
}

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) ::testing::GTEST_FLAG(output) = "";
  const int rc = RUN_ALL_TESTS();
  MPI_Finalize();
  return rc;
}
