#pragma once
// Private: the XDMF 2 sidecar that lets ParaView read the field output as a time series of
// polylines. Pure text generation plus an atomic file replacement; no HDF5, no MPI.
#include <cstddef>
#include <string>
#include <vector>

namespace traverse::output::detail {

struct XdmfField {
  std::string name;
  std::size_t components = 1;
  std::vector<std::string> component_names;
};

struct XdmfModel {
  std::string h5_name;        ///< HDF5 file name as seen from the .xmf's folder
  std::size_t nodes = 0;      ///< global node count
  std::vector<double> times;  ///< one entry per written step [s]
  std::vector<XdmfField> fields;
  int geometry_field = -1;    ///< index into fields of the 3-component geometry, -1: /mesh/position
};

/// The complete .xmf text: a temporal collection of one Uniform grid per step.
std::string xdmf_document(const XdmfModel& model);

/// Writes `text` to `path` + ".tmp" and renames it onto `path` (atomic on POSIX).
/// Throws OutputError on failure.
void replace_file(const std::string& path, const std::string& text);

}  // namespace traverse::output::detail
