// Writes the sample run step after step with a pause, forever (or up to argv[2] steps),
// so that test_output_kill can SIGKILL it mid-run. Every rank prints "pid <pid>" at start;
// rank 0 prints "step <k> flushed <f>" once write_step(k) returned, f being the steps then
// in the file and announced. flush_s: the writer's flush interval (default: the Writer's).
// Usage: output_kill_writer FILE [max_steps [pause_ms [flush_s]]]
#include <mpi.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <thread>

#include "sample_run.hpp"

using namespace traverse::output;

int main(int argc, char** argv) {
  MPI_Init(&argc, &argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (argc < 2) {
    if (rank == 0) std::fprintf(stderr, "usage: %s FILE [max_steps [pause_ms [flush_s]]]\n", argv[0]);
    MPI_Finalize();
    return 2;
  }
  const long max_steps = argc > 2 ? std::atol(argv[2]) : 1000000;
  const long pause_ms = argc > 3 ? std::atol(argv[3]) : 100;
  std::printf("pid %ld\n", static_cast<long>(getpid()));
  std::fflush(stdout);
  int rc = 0;
  try {
    const NodeLayout l = sample::layout(MPI_COMM_WORLD);
    Writer w(MPI_COMM_WORLD, argv[1], true, sample::run_info(), l, sample::loads);
    if (argc > 4) w.set_intervals(std::atof(argv[4]), w.xdmf_interval());
    sample::declare(w);
    for (long k = 0; k < max_steps; ++k) {
      sample::write_step(w, l, static_cast<std::size_t>(k));
      if (rank == 0) {
        std::printf("step %ld flushed %zu\n", k, w.steps_flushed());
        std::fflush(stdout);
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(pause_ms));
    }
    w.finish();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "output_kill_writer: %s\n", e.what());
    rc = 1;
  }
  MPI_Finalize();
  return rc;
}
