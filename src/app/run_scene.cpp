// One validated scene, run by the runner of its model.
#include <stdexcept>

#include "run.hpp"

namespace traverse::app {

void run_scene(const scene::Scene& sc, const RunOptions& opt, MPI_Comm comm) {
  switch (sc.model) {
    case scene::Model::Beam:
      run_beam(sc, opt, comm);
      break;
    case scene::Model::Rod:
      if (sc.continuation.enabled) {
        run_statics(sc, opt, comm);
      } else {
        run_rod(sc, opt, comm);
      }
      break;
    default:
      throw std::logic_error("traverse run: model not handled");
  }
}

}  // namespace traverse::app
