#pragma once
// Private helpers shared by the output writers: collective agreement on errors and the
// check of an output location before anything is created.
#include <mpi.h>

#include <string>

namespace traverse::output::detail {

/// All ranks learn whether every rank is fine; if not, all throw the OutputError message of
/// the lowest failing rank.
void agree(MPI_Comm comm, bool ok, const std::string& message);

/// Check of the output location (run it on one rank): empty string when `path` (and
/// `sidecar`, if not empty) may be created; otherwise why not (missing or unwritable folder,
/// existing file without `overwrite`, ...).
std::string check_location(const std::string& path, const std::string& sidecar, bool overwrite);

}  // namespace traverse::output::detail
