#pragma once
// Clean stop on SIGINT / SIGTERM: the handler only records the signal; the run loops ask
// interrupt_requested() (collective) after each time step and, when it answers non-zero,
// stop at that step on every rank, mark the output file and throw Interrupted. A second
// signal of the same kind is not caught (default action: the process ends at once).
// Under mpirun the signal may reach only some ranks (or arrive as SIGTERM from mpirun):
// the decision is an MPI_Allreduce, so all ranks stop at the same step.
#include <mpi.h>

#include <csignal>
#include <functional>
#include <stdexcept>
#include <string>

namespace traverse::output {
class Writer;
}

namespace traverse::app {

class Progress;

/// Installs the SIGINT and SIGTERM handlers (idempotent).
void install_interrupt_handlers();

/// The handlers of install_interrupt_handlers for its lifetime, in a process that has its own
/// (the Python module's runs): puts back the handlers it found and forgets the signal received.
class InterruptScope {
 public:
  InterruptScope();
  ~InterruptScope();
  InterruptScope(const InterruptScope&) = delete;
  InterruptScope& operator=(const InterruptScope&) = delete;

 private:
  struct sigaction int_{}, term_{};
};

/// The signal this rank received (0: none). Not collective.
int local_interrupt_signal();

/// Collective over `comm`: the largest signal number any rank received, 0 if none.
int interrupt_requested(MPI_Comm comm);

/// Thrown (on every rank, after the output file was marked and closed by unwinding) when a
/// run stops on a signal. main() exits with 128 + signal (130 for SIGINT).
class Interrupted : public std::runtime_error {
 public:
  Interrupted(int signal, std::string output, std::string status, const std::string& message)
      : std::runtime_error(message), signal_(signal), output_(std::move(output)), status_(std::move(status)) {}
  int signal() const { return signal_; }
  const std::string& output() const { return output_; }  ///< the output file
  const std::string& status() const { return status_; }  ///< its final `status` attribute
 private:
  int signal_;
  std::string output_, status_;
};

/// Ends a run that `signal` stopped at time t [s] (`where`: the step, e.g. "time step 12"):
/// closes the progress line, stores the restart point (`store`, when given), marks the output
/// file "interrupted at t = ... (where, SIGINT); N output steps written; continue with traverse
/// run --restart OUT" and throws Interrupted with that message.
[[noreturn]] void stop_interrupted_run(int signal, double t, const std::string& where, output::Writer& writer,
                                       const std::string& output, Progress& progress,
                                       const std::function<void()>& store = {});

/// Name of a signal for messages ("SIGINT", "SIGTERM", "SIGKILL"; "signal 77" for one without a name).
std::string signal_name(int signal);

}  // namespace traverse::app
