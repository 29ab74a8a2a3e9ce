#pragma once
// Private: the XDMF 3 sidecar that lets ParaView (Xdmf3ReaderS and the legacy XDMFReader)
// and meshio's XDMF time-series reader read the field output as a time series of polylines.
//
// Every node array of every step is a whole HDF5 dataset, "/xdmf/<array>/<step>": a virtual
// dataset (HDF5 >= 1.10) that maps step <step> of "/fields/<field>" (components
// [first, first + count)), so that readers without hyperslab support (Xdmf3, meshio) read it
// and no data is stored twice. This header has the naming rules (shared by the Writer and by
// the `traverse xdmf` tool), the text generation and the atomic file replacement; no HDF5, no MPI.
#include <cstddef>
#include <ostream>
#include <string>
#include <vector>

namespace traverse::output::detail {

/// What the view planning needs to know of a field.
struct XdmfFieldInfo {
  std::string name;
  std::size_t components = 1;
  std::vector<std::string> component_names;
  bool geometry = false;  ///< marked as the node positions (FieldSpec::geometry)
  bool sidecar = true;    ///< FieldSpec::sidecar: false, no array (unless it is the geometry)
};

/// One node array of the sidecar: components [first, first + count) of a field, count 1 or 3.
struct XdmfView {
  std::string array;      ///< array name in the sidecar, also the group /xdmf/<array>
  std::size_t field = 0;  ///< index into the field list
  std::size_t first = 0;  ///< first component
  std::size_t count = 1;  ///< 1 (Scalar) or 3 (Vector)
};

struct XdmfPlan {
  std::vector<XdmfView> views;
  int geometry = -1;  ///< index into views of the node positions, -1: /mesh/position
};

/// The arrays of a list of fields: 1 component -> one Scalar named like the field,
/// 3 -> one Vector; 3m components whose names come in triples <P>x, <P>y, <P>z -> m Vectors
/// named <P> (the rod's R -> d1, d2, d3); otherwise one Scalar per component, <field>_<component>.
/// A name already taken (or "s") gets the prefix <field>_. The geometry is the view of the field
/// marked geometry, else of a 3-component field named "r", else none. Fields with sidecar
/// false have no array.
XdmfPlan plan_views(const std::vector<XdmfFieldInfo>& fields);

/// The HDF5 file as the sidecar names it: its absolute path. ParaView's Xdmf3 reader joins a
/// relative name to the folder of the .xmf as given to it, and a sidecar opened without a folder
/// ("run.xmf") then reads "run.xmfrun.h5"; an absolute name is read the same from anywhere
/// (and from a sidecar that `traverse xdmf -o` writes into another folder).
std::string sidecar_h5_name(const std::string& h5_path);

struct XdmfModel {
  std::string h5_name;        ///< the HDF5 file as the sidecar names it (sidecar_h5_name)
  std::size_t nodes = 0;      ///< global node count
  std::vector<double> times;  ///< one entry per step [s]
  std::vector<XdmfView> arrays;
  int geometry = -1;          ///< index into arrays, -1: /mesh/position
  std::size_t loads = 0;      ///< moving loads
  std::vector<double> sigma;  ///< steps x loads [m]
  /// steps x loads x load_width(): each load's position (x, y, z) on the structure, then the
  /// values of every array there (in the order of `arrays`), interpolated like the position.
  std::vector<double> load_values;
  std::size_t load_width() const {
    std::size_t w = 3;
    for (const auto& a : arrays) w += a.count;
    return w;
  }
};

/// The complete .xmf text (XDMF 3): a temporal collection "loads" of one Polyvertex grid per
/// step (a point at each moving load, with the structure's point arrays: s = sigma and every
/// array's value at the load; only when every sigma is finite), then the temporal collection
/// "structure" of one Polyline grid per step with the point arrays s and the views. Both
/// grids carry the same arrays: ParaView colours a multiblock by an array only when every
/// block has it. Identical models give identical text. Written to `out` in pieces of about
/// 64 KiB (never one string of the whole document).
void write_xdmf_document(const XdmfModel& model, std::ostream& out);

/// Interpolates at arclength `sigma` along the polyline through the nodes [first, first + n)
/// (global indices; `s` and `values` (n x width, node-major) hold exactly those nodes, the
/// structure has `global_nodes` nodes): the segment (j, j+1) with s_j <= sigma < s_{j+1}
/// holds it; below s_0 the first segment and from s_{N-1} on the last one (extrapolated
/// linearly). Writes `width` values to `out`; returns false if none of the given segments
/// holds sigma (or sigma is not finite).
bool load_point(std::size_t global_nodes, std::size_t first, std::size_t n, const double* s, const double* values,
                std::size_t width, double sigma, double* out);

/// Writes the document of `model` (write_xdmf_document) to `path` + ".tmp" and renames it onto
/// `path` (atomic on POSIX). Throws OutputError on failure.
void write_xdmf_file(const std::string& path, const XdmfModel& model);

}  // namespace traverse::output::detail
