#pragma once
// A stop request polled by long computations outside a run's time loop (the Newton iterations
// of a static initial state), so that a run stops within an iteration of SIGINT / SIGTERM
// during its set-up too. The application installs the hook (traverse run: the signal handlers'
// flag, decided over the run's ranks where the computation is distributed); a computation that
// finds a stop requested throws StopRequested. Without a hook nothing is ever requested.
#include <functional>
#include <stdexcept>
#include <string>

namespace traverse {

class StopRequested : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

/// The installed hook (empty: none). Polled at the same points on every rank of a distributed
/// computation, so a hook may be collective.
inline std::function<bool()>& stop_hook() {
  static std::function<bool()> hook;
  return hook;
}

/// Throws StopRequested naming `where` when the hook asks to stop.
inline void throw_if_stop_requested(const std::string& where) {
  if (stop_hook() && stop_hook()()) throw StopRequested("stopped during " + where);
}

}  // namespace traverse
