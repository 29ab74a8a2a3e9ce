#include "hand_over.hpp"

#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "restart.hpp"
#include "rod_setup.hpp"
#include "traverse/scene/scene.hpp"

namespace traverse::app {

bool needs_trilinos(const CommandLine& cl, const Launch& launch, Prepared& prepared) {
  using Command = CommandLine::Command;
  switch (cl.command) {
    case Command::Help:
    case Command::Version:
    case Command::Check:
    case Command::Xdmf: return false;
    case Command::Sweep:  // each case runs in this process (one rank each under a launcher)
      prepared.sweep = plan_sweep(cl);
      return prepared.sweep->needs_trilinos;
    case Command::Run:
      if (launch.by_launcher) return true;
      prepared.scene = cl.restart.empty() ? scene::load_scene(cl.scene, cl.overrides)
                                          : restart_scene(cl.restart, cl.scene, cl.overrides);
      return scene_needs_trilinos(*prepared.scene);
    default: throw std::logic_error("needs_trilinos: command not handled");
  }
}

bool scene_needs_trilinos(const scene::Scene& sc) {
  if (sc.model != scene::Model::Rod) return false;
  return sc.continuation.enabled || needs_tpetra(sc, build_rod_model(sc), MPI_COMM_NULL);
}

void hand_over_to_trilinos(char** argv) {
  std::error_code ec;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) throw std::runtime_error("cannot find this executable's directory (/proc/self/exe: " + ec.message() + ")");
  const std::string full = (self.parent_path() / "traverse-trilinos").string();
  argv[0] = const_cast<char*>(full.c_str());
  execv(full.c_str(), argv);
  throw std::runtime_error("cannot start " + full + " (" + std::strerror(errno) +
                           "), which runs what needs Trilinos: build it beside traverse (cmake --build builds both)");
}

}  // namespace traverse::app
