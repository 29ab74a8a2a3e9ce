#include "interrupt.hpp"

#include <sys/types.h>
#include <unistd.h>

#include <csignal>
#include <cstring>

#include "traverse/core/comm.hpp"

namespace traverse::app {

namespace {

volatile std::sig_atomic_t g_signal = 0;

// A sweep's worker processes (forward_interrupts_to), written before the handlers can see them.
pid_t g_workers[kMaxForwarded];
volatile std::sig_atomic_t g_worker_count = 0;

// A worker's parent (become_interrupt_worker); 0 in any other process.
pid_t g_parent = 0;
volatile std::sig_atomic_t g_own_signal = 0;  ///< a worker: a signal that did not come from its parent

extern "C" void on_signal(int sig) {
  g_signal = sig;
  for (std::sig_atomic_t i = 0; i < g_worker_count; ++i) kill(g_workers[i], sig);
}

// A worker's handler: a signal forwarded by the parent only asks to stop (the same Ctrl-C or
// `timeout` may also reach the worker directly); a second signal of its own ends it at once.
extern "C" void on_worker_signal(int sig, siginfo_t* info, void*) {
  if (info != nullptr && info->si_pid == g_parent && info->si_code == SI_USER) {
    if (g_signal == 0) g_signal = sig;
    return;
  }
  if (g_own_signal != 0) {
    signal(sig, SIG_DFL);
    raise(sig);
    return;
  }
  g_own_signal = sig;
  g_signal = sig;
}

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

void forward_interrupts_to(const pid_t* workers, int count) {
  sigset_t all, old;
  sigfillset(&all);
  sigprocmask(SIG_BLOCK, &all, &old);
  const int n = count < kMaxForwarded ? count : kMaxForwarded;
  for (int i = 0; i < n; ++i) g_workers[i] = workers[i];
  g_worker_count = n;
  sigprocmask(SIG_SETMASK, &old, nullptr);
}

void become_interrupt_worker(pid_t parent) {
  g_worker_count = 0;
  g_parent = parent;
  g_own_signal = 0;
  struct sigaction sa;
  std::memset(&sa, 0, sizeof sa);
  sa.sa_sigaction = on_worker_signal;
  sa.sa_flags = SA_SIGINFO;  // who sent it; the handler itself ends the process on a second one
  handle_stop_signals(sa);
}

int local_interrupt_signal() { return static_cast<int>(g_signal); }

int interrupt_requested(MPI_Comm comm) {
  int mine = local_interrupt_signal(), any = 0;
  par::allreduce(&mine, &any, 1, MPI_INT, MPI_MAX, comm);
  return any;
}

std::string signal_name(int signal) {
  if (const char* abbrev = sigabbrev_np(signal)) return std::string("SIG") + abbrev;
  return "signal " + std::to_string(signal);
}

}  // namespace traverse::app
