// Writes the sample run for the Python reader check (tests/output/check_roundtrip.py):
//   DIR/sample.h5         5 steps, restart, status "complete"
//   DIR/sample_failed.h5  2 steps, status "failed: Newton iteration diverged"
// Usage: output_sample_writer DIR   (DIR is created if needed)
#include <mpi.h>

#include <cstdio>
#include <filesystem>
#include <string>

#include "sample_run.hpp"

using namespace traverse::output;

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rc = 0;
  try {
    if (argc != 2) throw OutputError("usage: output_sample_writer DIR");
    const std::string dir = argv[1];
    int rank = 0;
    MPI_Comm_rank(MPI_COMM_WORLD, &rank);
    if (rank == 0) std::filesystem::create_directories(dir);
    MPI_Barrier(MPI_COMM_WORLD);
    const NodeLayout l = sample::layout(MPI_COMM_WORLD);
    {
      Writer w(MPI_COMM_WORLD, dir + "/sample.h5", true, sample::run_info(), l, sample::loads);
      sample::declare(w);
      for (std::size_t k = 0; k < 5; ++k) sample::write_step(w, l, k);
      sample::write_restart(w, l, 4);
      w.finish();
    }
    {
      Writer w(MPI_COMM_WORLD, dir + "/sample_failed.h5", true, sample::run_info(), l,
               sample::loads);
      sample::declare(w);
      for (std::size_t k = 0; k < 2; ++k) sample::write_step(w, l, k);
      w.fail("Newton iteration diverged");
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "output_sample_writer: %s\n", e.what());
    rc = 1;
  }
  MPI_Finalize();
  return rc;
}
