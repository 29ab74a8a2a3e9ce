#pragma once
// The exception types the output module throws.
#include <stdexcept>
#include <string>

namespace traverse::output {

/// Raised for every failure of the output module: refusal to overwrite, a missing or
/// unwritable folder, a failed HDF5 call (the message names the call and the object), and
/// misuse of the API (wrong sizes, calls out of order). In collective calls all ranks throw
/// the same error whenever the failure can be detected collectively (argument checks,
/// path checks); see docs/output.md.
class OutputError : public std::runtime_error {
 public:
  explicit OutputError(const std::string& what) : std::runtime_error(what) {}
};

/// A restart that cannot go on (no usable restart point, outputs that differ from the
/// scene, a file that cannot be read or moved aside): bad input of the command line. Not an
/// OutputError, so that the restart functions' own wrapping of OutputError leaves it alone.
class RestartError : public std::runtime_error {
 public:
  explicit RestartError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace traverse::output
