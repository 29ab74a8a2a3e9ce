#include "traverse/output/continuation_writer.hpp"

#include <cstdint>

#include "hdf5_handle.hpp"
#include "location.hpp"
#include "traverse/output/output_error.hpp"

namespace traverse::output {

using detail::check;
using detail::check_id;
using detail::Handle;

namespace {

Handle group(hid_t loc, const std::string& name) {
  return detail::group_handle(check_id(H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
                                       "H5Gcreate2", name));
}

// An extendible 1-D dataset of `type`.
Handle series(hid_t loc, const std::string& name, hid_t type) {
  const hsize_t dims[1] = {0}, maxdims[1] = {H5S_UNLIMITED}, chunk[1] = {256};
  Handle space = detail::space_handle(check_id(H5Screate_simple(1, dims, maxdims), "H5Screate_simple", name));
  Handle dcpl = detail::plist_handle(check_id(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate", name));
  check(H5Pset_chunk(dcpl.get(), 1, chunk), "H5Pset_chunk", name);
  return detail::dataset_handle(check_id(
      H5Dcreate2(loc, name.c_str(), type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT), "H5Dcreate2", name));
}

void append(hid_t dataset, hid_t memtype, const void* value, const std::string& name) {
  hsize_t n = detail::dataset_dims(dataset, name)[0];
  const hsize_t next[1] = {n + 1};
  check(H5Dset_extent(dataset, next), "H5Dset_extent", name);
  Handle file_space = detail::space_handle(check_id(H5Dget_space(dataset), "H5Dget_space", name));
  const hsize_t start[1] = {n}, count[1] = {1};
  check(H5Sselect_hyperslab(file_space.get(), H5S_SELECT_SET, start, nullptr, count, nullptr),
        "H5Sselect_hyperslab", name);
  Handle mem = detail::space_handle(check_id(H5Screate_simple(1, count, nullptr), "H5Screate_simple", name));
  check(H5Dwrite(dataset, memtype, mem.get(), file_space.get(), H5P_DEFAULT, value), "H5Dwrite", name);
}

void matrix(hid_t loc, const std::string& name, const std::vector<double>& v, hsize_t cols) {
  const hsize_t dims[2] = {v.size() / cols, cols};
  Handle space = detail::space_handle(check_id(H5Screate_simple(2, dims, nullptr), "H5Screate_simple", name));
  Handle ds = detail::dataset_handle(check_id(
      H5Dcreate2(loc, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT),
      "H5Dcreate2", name));
  check(H5Dwrite(ds.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data()), "H5Dwrite", name);
}

void write_state_group(hid_t loc, const std::string& name, const NodalState& st) {
  Handle g = group(loc, name);
  matrix(g.get(), "r", st.r, 3);
  matrix(g.get(), "R", st.R, 9);
  matrix(g.get(), "kappa", st.kappa, 3);
  matrix(g.get(), "n", st.n, 3);
  detail::write_string_attribute(g.get(), "description",
                                 "static rod state: r centreline (fixed frame) [m], R rows d1 d2 d3 (fixed "
                                 "components), kappa curvature [1/m] and n contact force [N] in body components");
}

}  // namespace

struct ContinuationWriter::Impl {
  MPI_Comm comm = MPI_COMM_NULL;
  int rank = 0;
  std::string path;
  std::vector<std::string> probe_names;
  std::string parameter;
  Handle file, cont, bif;
  Handle par_ds, branch_ds, unstable_ds, critical_ds;
  std::vector<Handle> probe_ds;
  Handle bif_type, bif_branch, bif_located, bif_par;
  std::vector<Handle> bif_probe;
  std::size_t points = 0, bifurcations = 0;
  bool finished = false;

  void flush() { check(H5Fflush(file.get(), H5F_SCOPE_LOCAL), "H5Fflush", path); }
  void status(const std::string& s) {
    detail::write_string_attribute(file.get(), "status", s);
    flush();
  }
};

ContinuationWriter::ContinuationWriter(MPI_Comm comm, const std::string& path, bool overwrite, const RunInfo& info,
                                       const std::vector<double>& s, const std::string& parameter,
                                       const std::string& parameter_unit, const std::vector<std::string>& probes,
                                       const std::vector<std::string>& probe_units)
    : impl_(std::make_unique<Impl>()) {
  detail::silence_hdf5_errors();
  Impl& w = *impl_;
  w.comm = comm;
  MPI_Comm_rank(comm, &w.rank);
  w.path = path;
  w.parameter = parameter;
  w.probe_names = probes;
  std::string bad;
  if (probes.size() != probe_units.size()) bad = "output: probe names and units differ in number";
  for (const auto& n : probes)
    if (!detail::valid_name(n) || n == parameter || n == "unstable_modes" || n == "critical_eigenvalue" || n == "branch")
      bad = "output: invalid or reserved continuation probe name '" + n + "'";
  if (bad.empty() && w.rank == 0) bad = detail::check_location(path, "", overwrite);
  detail::agree(comm, bad.empty(), bad);
  std::string error;
  if (w.rank == 0) {
    try {
      w.file = detail::file_handle(check_id(H5Fcreate(path.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT),
                                            "H5Fcreate", path));
      const hid_t f = w.file.get();
      detail::write_string_attribute(f, "traverse_version", info.version);
      detail::write_string_attribute(f, "command_line", info.command_line);
      detail::write_string_attribute(f, "scene", info.scene_text);
      detail::write_string_attribute(f, "scene_file", info.scene_file);
      detail::write_string_attribute(f, "model", info.model);
      detail::write_string_attribute(f, "kind", "continuation");
      detail::write_int_attribute(f, "points_written", 0);
      Handle mesh = group(f, "mesh");
      matrix(mesh.get(), "s", s, 1);
      w.cont = group(f, "continuation");
      w.par_ds = series(w.cont.get(), parameter, H5T_IEEE_F64LE);
      detail::write_string_attribute(w.par_ds.get(), "units", parameter_unit);
      detail::write_string_attribute(w.par_ds.get(), "description", "the continued parameter");
      for (size_t i = 0; i < probes.size(); ++i) {
        w.probe_ds.push_back(series(w.cont.get(), probes[i], H5T_IEEE_F64LE));
        detail::write_string_attribute(w.probe_ds.back().get(), "units", probe_units[i]);
      }
      w.unstable_ds = series(w.cont.get(), "unstable_modes", H5T_STD_I64LE);
      detail::write_string_attribute(w.unstable_ds.get(), "description",
                                     "number of small-vibration eigenvalues omega^2 < 0 (-1: not computed)");
      w.critical_ds = series(w.cont.get(), "critical_eigenvalue", H5T_IEEE_F64LE);
      detail::write_string_attribute(w.critical_ds.get(), "units", "1/s^2");
      w.branch_ds = series(w.cont.get(), "branch", H5T_STD_I64LE);
      w.bif = group(f, "bifurcations");
      Handle strtype = detail::type_handle(check_id(H5Tcopy(H5T_C_S1), "H5Tcopy", path));
      check(H5Tset_size(strtype.get(), 16), "H5Tset_size", path);
      w.bif_type = series(w.bif.get(), "type", strtype.get());
      w.bif_branch = series(w.bif.get(), "branch", H5T_STD_I64LE);
      w.bif_located = series(w.bif.get(), "located", H5T_STD_I64LE);
      w.bif_par = series(w.bif.get(), parameter, H5T_IEEE_F64LE);
      for (const auto& n : probes) w.bif_probe.push_back(series(w.bif.get(), n, H5T_IEEE_F64LE));
      Handle states = group(f, "states");
      w.status("running");
    } catch (const OutputError& e) {
      error = e.what();
    }
  }
  detail::agree(comm, error.empty(), error);
}

ContinuationWriter::~ContinuationWriter() {
  if (!impl_ || impl_->rank != 0 || !impl_->file.valid()) return;
  try {
    if (!impl_->finished) impl_->status("failed: output closed before finish() or fail()");
  } catch (...) {
  }
}

void ContinuationWriter::add_point(int branch, double parameter, const std::vector<double>& probes,
                                   int unstable_modes, double critical_eigenvalue) {
  Impl& w = *impl_;
  if (probes.size() != w.probe_names.size()) throw OutputError("output: continuation point has the wrong probe count");
  if (w.rank == 0) {
    append(w.par_ds.get(), H5T_NATIVE_DOUBLE, &parameter, w.parameter);
    for (size_t i = 0; i < probes.size(); ++i) append(w.probe_ds[i].get(), H5T_NATIVE_DOUBLE, &probes[i], w.probe_names[i]);
    const std::int64_t u = unstable_modes, b = branch;
    append(w.unstable_ds.get(), H5T_NATIVE_INT64, &u, "unstable_modes");
    append(w.critical_ds.get(), H5T_NATIVE_DOUBLE, &critical_eigenvalue, "critical_eigenvalue");
    append(w.branch_ds.get(), H5T_NATIVE_INT64, &b, "branch");
    w.flush();
    detail::write_int_attribute(w.file.get(), "points_written", static_cast<std::int64_t>(w.points + 1));
    w.flush();
  }
  ++w.points;
}

void ContinuationWriter::add_bifurcation(const std::string& type, int branch, bool located, double parameter,
                                         const std::vector<double>& probes, const NodalState& state) {
  Impl& w = *impl_;
  if (probes.size() != w.probe_names.size()) throw OutputError("output: bifurcation has the wrong probe count");
  if (w.rank == 0) {
    char t[16] = {};
    type.copy(t, sizeof t - 1);
    Handle strtype = detail::type_handle(check_id(H5Tcopy(H5T_C_S1), "H5Tcopy", w.path));
    check(H5Tset_size(strtype.get(), 16), "H5Tset_size", w.path);
    append(w.bif_type.get(), strtype.get(), t, "bifurcations/type");
    const std::int64_t b = branch, l = located ? 1 : 0;
    append(w.bif_branch.get(), H5T_NATIVE_INT64, &b, "bifurcations/branch");
    append(w.bif_located.get(), H5T_NATIVE_INT64, &l, "bifurcations/located");
    append(w.bif_par.get(), H5T_NATIVE_DOUBLE, &parameter, "bifurcations/" + w.parameter);
    for (size_t i = 0; i < probes.size(); ++i)
      append(w.bif_probe[i].get(), H5T_NATIVE_DOUBLE, &probes[i], "bifurcations/" + w.probe_names[i]);
    write_state_group(w.bif.get(), "state_" + std::to_string(w.bifurcations), state);
    w.flush();
  }
  ++w.bifurcations;
}

void ContinuationWriter::write_state(const std::string& name, const NodalState& state) {
  Impl& w = *impl_;
  if (!detail::valid_name(name)) throw OutputError("output: invalid state name '" + name + "'");
  if (w.rank == 0) {
    Handle states = detail::group_handle(check_id(H5Gopen2(w.file.get(), "states", H5P_DEFAULT), "H5Gopen2", "states"));
    if (H5Lexists(states.get(), name.c_str(), H5P_DEFAULT) > 0)
      check(H5Ldelete(states.get(), name.c_str(), H5P_DEFAULT), "H5Ldelete", name);
    write_state_group(states.get(), name, state);
    w.flush();
  }
}

void ContinuationWriter::finish() {
  Impl& w = *impl_;
  if (w.rank == 0) w.status("complete");
  w.finished = true;
}

void ContinuationWriter::fail(const std::string& reason) {
  Impl& w = *impl_;
  if (w.rank == 0) w.status("failed: " + reason);
  w.finished = true;
}

std::size_t ContinuationWriter::points_written() const { return impl_->points; }

NodalState read_state(const std::string& path, const std::string& name) {
  detail::silence_hdf5_errors();
  const hid_t id = H5Fopen(path.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (id < 0) throw OutputError(path + ": cannot open it as an HDF5 file");
  Handle file = detail::file_handle(id);
  const std::string g = "/states/" + name;
  if (H5Lexists(file.get(), "/states", H5P_DEFAULT) <= 0 || H5Lexists(file.get(), g.c_str(), H5P_DEFAULT) <= 0)
    throw OutputError(path + ": no state '" + name + "' (expected the group " + g +
                      " written by a continuation run)");
  NodalState st;
  auto read = [&](const char* what, std::vector<double>& out, hsize_t cols) {
    const std::string ds_name = g + "/" + what;
    Handle ds = detail::dataset_handle(check_id(H5Dopen2(file.get(), ds_name.c_str(), H5P_DEFAULT), "H5Dopen2", ds_name));
    const auto dims = detail::dataset_dims(ds.get(), ds_name);
    if (dims.size() != 2 || dims[1] != cols) throw OutputError(path + ": " + ds_name + " has the wrong shape");
    out.resize(dims[0] * dims[1]);
    check(H5Dread(ds.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()), "H5Dread", ds_name);
  };
  read("r", st.r, 3);
  read("R", st.R, 9);
  read("kappa", st.kappa, 3);
  read("n", st.n, 3);
  return st;
}

}  // namespace traverse::output
