#pragma once
// The XDMF sidecar of an existing output file, rewritten from the file alone: what
// `traverse xdmf OUT.h5` does (docs/output.md, "The XDMF sidecar"). Serial, no MPI.
#include <cstddef>
#include <string>

#include "traverse/output/output_error.hpp"

namespace traverse::output {

struct SidecarResult {
  std::string xmf_path;           ///< the sidecar written
  std::size_t steps = 0;          ///< output steps it describes (the file's steps_written)
  std::size_t views_created = 0;  ///< per-step views (/xdmf/...) that were missing and were added
};

/// (Re)writes the XDMF sidecar of the traverse time-series output `h5_path` (complete,
/// failed, interrupted or killed: steps 0 .. steps_written-1) to `xmf_path` (default: the
/// .h5 path with extension .xmf), atomically. The same file gives the same text as the
/// Writer's own sidecar. The file is only read, unless per-step views are missing (files of
/// older traverse versions): then they are added, which needs write access. Do not run it on
/// a file that a run is still writing. Throws OutputError naming the file and the problem.
SidecarResult write_sidecar(const std::string& h5_path, const std::string& xmf_path = {});

}  // namespace traverse::output
