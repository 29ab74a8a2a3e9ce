#include "interrupt.hpp"

#include <csignal>
#include <cstring>
#include <sstream>

#include "progress.hpp"
#include "traverse/core/comm.hpp"
#include "traverse/output/writer.hpp"
#include "traverse/time/time_integrator.hpp"

namespace traverse::app {

namespace {

volatile std::sig_atomic_t g_signal = 0;

extern "C" void on_signal(int sig) { g_signal = sig; }

// SIGINT and SIGTERM to the handler of `sa` (`sa_flags`: SA_RESTART always, so that MPI/HDF5
// calls in progress resume instead of failing with EINTR).
void handle_stop_signals(struct sigaction sa) {
  sigemptyset(&sa.sa_mask);
  sa.sa_flags |= SA_RESTART;
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

}  // namespace

void install_interrupt_handlers() {
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_handler = on_signal;
  sa.sa_flags = SA_RESETHAND;  // a second Ctrl-C kills at once
  handle_stop_signals(sa);
}

InterruptScope::InterruptScope() {
  sigaction(SIGINT, nullptr, &int_);
  sigaction(SIGTERM, nullptr, &term_);
  g_signal = 0;
  install_interrupt_handlers();
}

InterruptScope::~InterruptScope() {
  sigaction(SIGINT, &int_, nullptr);
  sigaction(SIGTERM, &term_, nullptr);
  g_signal = 0;
}

int local_interrupt_signal() { return static_cast<int>(g_signal); }

int interrupt_requested(MPI_Comm comm) {
  int mine = local_interrupt_signal(), any = 0;
  par::allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, comm);
  return any;
}

void stop_interrupted_run(int signal, double t, const std::string& where, output::Writer& writer,
                          const std::string& output, Progress& progress, const std::function<void()>& store) {
  progress.done();
  std::ostringstream os;
  os.precision(12);
  os << "interrupted at t = " << t << " s (" << where << ", " << signal_name(signal) << "); " << writer.steps_written()
     << " output steps written; continue with traverse run --restart " << output;
  if (store) store();
  writer.fail(os.str());
  throw Interrupted(signal, output, os.str(), os.str());
}

std::string signal_name(int signal) {
  if (signal == time::kStopRequested) return "stopped by the step callback";
  if (const char* abbrev = sigabbrev_np(signal)) return std::string("SIG") + abbrev;
  return "signal " + std::to_string(signal);
}

}  // namespace traverse::app
