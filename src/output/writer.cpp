#include "traverse/output/writer.hpp"

#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <utility>

#include "hdf5_handle.hpp"
#include "location.hpp"
#include "traverse/core/comm.hpp"
#include "xdmf.hpp"

namespace traverse::output {

using detail::check;
using detail::check_id;
using detail::Handle;
using detail::agree;
using detail::check_location;

namespace {

namespace fs = std::filesystem;

constexpr hsize_t unlimited = H5S_UNLIMITED;

std::string sidecar_path(const std::string& path) {
  fs::path p(path);
  p.replace_extension(".xmf");
  return p.string();
}

struct Series1 {
  std::string name;
  std::size_t components = 1;
  Handle dataset;
  bool matrix = false;  // rank-2 dataset (steps, components) instead of (steps,)
};

struct Field1 {
  FieldSpec spec;
  Handle dataset;
};

Handle create_group(hid_t loc, const std::string& name) {
  return detail::group_handle(check_id(
      H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "H5Gcreate2",
      "group " + name));
}

/// Creates a chunked dataset of doubles with an unlimited first dimension of extent 0.
Handle create_extendible(hid_t loc, const std::string& name, const std::vector<hsize_t>& tail,
                         const std::vector<hsize_t>& chunk) {
  std::vector<hsize_t> dims{0}, maxdims{unlimited};
  for (hsize_t d : tail) {
    dims.push_back(d);
    maxdims.push_back(d);
  }
  Handle space = detail::space_handle(check_id(
      H5Screate_simple(static_cast<int>(dims.size()), dims.data(), maxdims.data()),
      "H5Screate_simple", name));
  Handle dcpl = detail::plist_handle(check_id(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate", name));
  check(H5Pset_chunk(dcpl.get(), static_cast<int>(chunk.size()), chunk.data()), "H5Pset_chunk",
        name);
  check(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER), "H5Pset_fill_time", name);
  Handle dapl = detail::plist_handle(check_id(H5Pcreate(H5P_DATASET_ACCESS), "H5Pcreate", name));
  // No chunk cache: the kept steps are written in whole blocks at each flush, so a cache would
  // only hold every chunk of every series in memory until the file closes (docs/output.md).
  check(H5Pset_chunk_cache(dapl.get(), 0, 0, 1.0), "H5Pset_chunk_cache", name);
  return detail::dataset_handle(check_id(H5Dcreate2(loc, name.c_str(), H5T_IEEE_F64LE, space.get(),
                                                    H5P_DEFAULT, dcpl.get(), dapl.get()),
                                         "H5Dcreate2", name));
}

/// Creates a fixed-size contiguous dataset.
Handle create_fixed(hid_t loc, const std::string& name, hid_t type,
                    const std::vector<hsize_t>& dims) {
  Handle space = detail::space_handle(
      check_id(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr),
               "H5Screate_simple", name));
  Handle dcpl = detail::plist_handle(check_id(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate", name));
  check(H5Pset_fill_time(dcpl.get(), H5D_FILL_TIME_NEVER), "H5Pset_fill_time", name);
  return detail::dataset_handle(check_id(
      H5Dcreate2(loc, name.c_str(), type, space.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
      "H5Dcreate2", name));
}

/// Collective write of the block start/count of `dataset` (whose current extent is used);
/// `local` false: this rank contributes nothing.
void write_block(hid_t dataset, hid_t dxpl, hid_t memtype, const std::vector<hsize_t>& start,
                 const std::vector<hsize_t>& count, const void* data, bool local,
                 const std::string& what) {
  Handle fspace = detail::space_handle(check_id(H5Dget_space(dataset), "H5Dget_space", what));
  hsize_t n = 1;
  for (hsize_t c : count) n *= c;
  if (!local || n == 0) {
    check(H5Sselect_none(fspace.get()), "H5Sselect_none", what);
    const hsize_t one = 1;
    Handle mspace = detail::space_handle(
        check_id(H5Screate_simple(1, &one, nullptr), "H5Screate_simple", what));
    check(H5Sselect_none(mspace.get()), "H5Sselect_none", what);
    static const double dummy = 0.0;
    check(H5Dwrite(dataset, memtype, mspace.get(), fspace.get(), dxpl, &dummy), "H5Dwrite", what);
    return;
  }
  check(H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                            nullptr),
        "H5Sselect_hyperslab", what);
  // The memory space has the selection's shape: HDF5 then maps it onto the chunks by whole
  // blocks (a flat memory space makes it visit every element).
  Handle mspace = detail::space_handle(check_id(
      H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr), "H5Screate_simple", what));
  check(H5Dwrite(dataset, memtype, mspace.get(), fspace.get(), dxpl, data), "H5Dwrite", what);
}

void write_meta(hid_t obj, const std::string& units, const std::string& description) {
  detail::write_string_attribute(obj, "units", units);
  detail::write_string_attribute(obj, "description", description);
}

std::vector<std::string> default_component_names(std::size_t n) {
  std::vector<std::string> names;
  for (std::size_t i = 0; i < n; ++i) names.push_back(std::to_string(i));
  return names;
}

// Rows per chunk of a time series (/time, /sigma, probes): 64 KiB, so that reading a probe's
// whole time series touches few chunks.
hsize_t series_chunk_rows(std::size_t components) {
  return static_cast<hsize_t>(std::max<std::size_t>(1, 8192 / std::max<std::size_t>(components, 1)));
}

enum class State { running, finished, failed, closed };

using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t) { return std::chrono::duration<double>(Clock::now() - t).count(); }

}  // namespace

struct Writer::Impl {
  MPI_Comm comm = MPI_COMM_NULL;
  int rank = 0;
  int size = 1;
  std::string path, xmf_path, model;
  NodeLayout nodes;
  std::size_t moving_loads = 1;
  Handle dxpl;
  Handle file;
  Handle time_ds, sigma_ds;
  Handle probes_group, fields_group, xdmf_group;
  std::vector<Series1> probes;
  std::vector<Field1> fields;
  State state = State::running;

  // Steps: `steps` passed to write_step, `flushed` of them in the file and announced.
  std::size_t steps = 0, flushed = 0;
  std::vector<double> times;  // every step's time (for the sidecar)
  // Kept steps (flushed .. steps-1), row after row.
  std::vector<double> pend_time, pend_sigma;
  std::vector<std::vector<double>> pend_probe, pend_field;
  std::size_t field_bytes_per_step = 0;  // all ranks together

  // Sidecar: its views, and (rank 0) the loads at every flushed step.
  detail::XdmfPlan plan;
  std::vector<Handle> view_groups;
  std::vector<double> sigma_all, load_values_all;
  std::vector<double> reference_xyz;  // local nodes' /mesh/position
  std::vector<unsigned long long> ranges;  // every rank's (first node, node count)
  int prev_owner = MPI_PROC_NULL, next_owner = MPI_PROC_NULL;  // neighbours along the structure
  double halo_s = 0.0;  // s of the node after this rank's last, if next_owner exists

  double flush_seconds = 1.0, xdmf_seconds = 5.0, xdmf_wait = 5.0;
  Clock::time_point last_flush = Clock::now(), last_xdmf = Clock::now();

  void flush_file() {
    check(H5Fflush(file.get(), H5F_SCOPE_LOCAL), "H5Fflush", path);
    set_file_size(true);
  }
  // A kill -9 inside H5Fflush may land after HDF5 has written the superblock with its new end
  // of allocation (EOA) but before the blocks at the end of the file: the file would then be
  // shorter than its superblock says, which HDF5 refuses to open ("truncated file"). So after
  // each flush the file is made longer than any EOA the next flush can record (a hole: no
  // disk space; HDF5 opens a file longer than its EOA), and cut back to the EOA before it is
  // closed. The EOA: a flush that changed it sets the file's size to it (the MPI-IO driver's
  // truncate, or the POSIX driver's of one rank); one that did not leaves the
  // padded size, and the EOA is the one padded from. Call right after a flush, collectively.
  // `padded` false: exactly the EOA.
  MPI_Offset eoa_known = -1, padded_size = -1;
  void set_file_size(bool padded) {
    void* handle = nullptr;
    if (H5Fget_vfd_handle(file.get(), H5P_DEFAULT, &handle) < 0 || !handle) return;
    const bool posix = par::alone(comm);  // the sec2 driver: a file descriptor
    MPI_Offset size = 0, eoa = 0;
    if (posix) {
      // The POSIX driver does not see the padding (it truncates only when its own idea of the
      // end differs from the EOA): ask HDF5 for the EOA itself.
      struct stat st {};
      haddr_t a = 0;
      if (fstat(*static_cast<int*>(handle), &st) != 0 || H5Fget_eoa(file.get(), &a) < 0) return;
      size = static_cast<MPI_Offset>(st.st_size);
      eoa = static_cast<MPI_Offset>(a);
    } else {
      if (rank == 0 && MPI_File_get_size(*static_cast<MPI_File*>(handle), &size) != MPI_SUCCESS) size = -1;
      MPI_Bcast(&size, 1, MPI_OFFSET, 0, comm);
      if (size < 0) return;
      eoa = size == padded_size && eoa_known >= 0 ? eoa_known : size;
    }
    const MPI_Offset grown = eoa_known >= 0 && eoa > eoa_known ? eoa - eoa_known : 0;
    const MPI_Offset target = padded ? eoa + std::max<MPI_Offset>(MPI_Offset(64) << 20, 4 * grown) : eoa;
    if (target != size) {
      if (posix) (void)!ftruncate(*static_cast<int*>(handle), static_cast<off_t>(target));
      else MPI_File_set_size(*static_cast<MPI_File*>(handle), target);
    }
    eoa_known = eoa;
    padded_size = target;
  }
  void set_status(const std::string& status) {
    detail::write_string_attribute(file.get(), "status", status);
    flush_file();
  }
  void require_open(const char* what) const {
    if (state == State::closed || !file.valid())
      throw OutputError(std::string("output ") + what + " on a closed output file " + path);
  }
  void append_rows(hid_t dataset, std::size_t components, bool matrix, const double* rows, bool local,
                   const std::string& what);
  void flush_pending();
  void compute_load_points(std::size_t b);
  void write_xdmf();
  void write_xdmf_text();
  void close_all() noexcept;
  // Stages of the constructor.
  void check_layout(const NodeLayout& nodes, std::size_t loads);
  void check_output_location(bool overwrite);
  void create_file(bool overwrite);
  void write_run_attributes(const RunInfo& info);
  void create_series(std::size_t loads);
  void write_mesh();
  void create_groups();
};

void Writer::Impl::append_rows(hid_t dataset, std::size_t components, bool matrix, const double* rows, bool local,
                               const std::string& what) {
  const std::size_t b = steps - flushed;
  std::vector<hsize_t> dims{static_cast<hsize_t>(steps)};
  if (matrix) dims.push_back(components);
  check(H5Dset_extent(dataset, dims.data()), "H5Dset_extent", what);
  std::vector<hsize_t> start{static_cast<hsize_t>(flushed)}, count{static_cast<hsize_t>(b)};
  if (matrix) {
    start.push_back(0);
    count.push_back(components);
  }
  write_block(dataset, dxpl.get(), H5T_NATIVE_DOUBLE, start, count, rows, local, what);
}

// Where the moving loads of the kept steps sit on the structure and the arrays' values there
// (rank 0 keeps them for the sidecar): each rank interpolates on its own segments, the one
// after its last node included (that node's values come from the next rank), and rank 0
// sums the results (one rank holds each load).
void Writer::Impl::compute_load_points(std::size_t b) {
  const std::size_t L = moving_loads, n = nodes.count;
  std::size_t W = 3;
  for (const auto& v : plan.views) W += v.count;
  // Row of node i (local) at kept step k: position, then every view's components.
  auto node_row = [&](std::size_t k, std::size_t i, double* out) {
    if (plan.geometry < 0) {
      std::copy(reference_xyz.data() + 3 * i, reference_xyz.data() + 3 * i + 3, out);
    } else {
      const detail::XdmfView& g = plan.views[static_cast<std::size_t>(plan.geometry)];
      const std::size_t nc = fields[g.field].spec.components;
      const double* row = pend_field[g.field].data() + (k * n + i) * nc + g.first;
      std::copy(row, row + 3, out);
    }
    std::size_t at = 3;
    for (const auto& v : plan.views) {
      const std::size_t nc = fields[v.field].spec.components;
      const double* row = pend_field[v.field].data() + (k * n + i) * nc + v.first;
      std::copy(row, row + v.count, out + at);
      at += v.count;
    }
  };
  // The first node's row of every kept step goes to the previous rank.
  std::vector<double> send(W * b), halo(W * b, 0.0);
  if (n > 0)
    for (std::size_t k = 0; k < b; ++k) node_row(k, 0, &send[W * k]);
  if (!par::alone(comm))  // alone: no neighbours, the halo stays empty
    MPI_Sendrecv(send.data(), static_cast<int>(W * b), MPI_DOUBLE, n > 0 ? prev_owner : MPI_PROC_NULL, 7101,
                 halo.data(), static_cast<int>(W * b), MPI_DOUBLE, n > 0 ? next_owner : MPI_PROC_NULL, 7101, comm,
                 MPI_STATUS_IGNORE);
  const bool has_halo = n > 0 && next_owner != MPI_PROC_NULL;
  std::vector<double> s(nodes.s), rows(W * (n + 1));
  if (has_halo) s.push_back(halo_s);
  const std::size_t m = n + (has_halo ? 1 : 0);
  std::vector<double> mine(W * L * b, 0.0), all(rank == 0 ? W * L * b : 0);
  for (std::size_t k = 0; k < b && n > 0; ++k) {
    for (std::size_t i = 0; i < n; ++i) node_row(k, i, &rows[W * i]);
    if (has_halo) std::copy(&halo[W * k], &halo[W * k] + W, &rows[W * n]);
    for (std::size_t l = 0; l < L; ++l)
      detail::load_point(nodes.global_count, nodes.first, m, s.data(), rows.data(), W, pend_sigma[k * L + l],
                         &mine[W * (k * L + l)]);
  }
  if (size > 1) {
    MPI_Reduce(mine.data(), all.data(), static_cast<int>(mine.size()), MPI_DOUBLE, MPI_SUM, 0, comm);
  } else {
    all = std::move(mine);
  }
  if (rank == 0) {
    load_values_all.insert(load_values_all.end(), all.begin(), all.end());
    sigma_all.insert(sigma_all.end(), pend_sigma.begin(), pend_sigma.end());
  }
}

void Writer::Impl::flush_pending() {
  if (steps == flushed) return;
  const std::size_t b = steps - flushed;
  // 1. data of steps flushed..steps-1 (the extents grow; steps_written does not yet).
  append_rows(time_ds.get(), 1, false, pend_time.data(), rank == 0, "/time");
  append_rows(sigma_ds.get(), moving_loads, moving_loads > 1, pend_sigma.data(), rank == 0, "/sigma");
  for (std::size_t i = 0; i < probes.size(); ++i)
    append_rows(probes[i].dataset.get(), probes[i].components, probes[i].matrix, pend_probe[i].data(), rank == 0,
                "/probes/" + probes[i].name);
  for (std::size_t j = 0; j < fields.size(); ++j) {
    const Field1& f = fields[j];
    const std::string what = "/fields/" + f.spec.name;
    const hsize_t dims[3] = {static_cast<hsize_t>(steps), nodes.global_count, f.spec.components};
    check(H5Dset_extent(f.dataset.get(), dims), "H5Dset_extent", what);
    write_block(f.dataset.get(), dxpl.get(), H5T_NATIVE_DOUBLE, {flushed, nodes.first, 0},
                {b, nodes.count, f.spec.components}, pend_field[j].data(), nodes.count > 0, what);
  }
  // 2. the sidecar's views of these steps, and where the loads are.
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    const detail::XdmfView& view = plan.views[v];
    const FieldSpec& f = fields[view.field].spec;
    const std::string what = "/xdmf/" + view.array;
    const hsize_t N = nodes.global_count;
    if (sizeof(double) * N * view.count > detail::max_copied_view_bytes) {
      for (std::size_t k = flushed; k < steps; ++k)
        detail::create_view(view_groups[v].get(), k, "/fields/" + f.name, N, f.components, view.first, view.count,
                            what);
      continue;
    }
    // Small: copies, the same values on every rank (gathered).
    const std::size_t c = view.count, nc = f.components;
    std::vector<double> mine(b * nodes.count * c);
    for (std::size_t k = 0; k < b; ++k)
      for (std::size_t i = 0; i < nodes.count; ++i)
        for (std::size_t q = 0; q < c; ++q)
          mine[(k * nodes.count + i) * c + q] = pend_field[view.field][(k * nodes.count + i) * nc + view.first + q];
    std::vector<double> all;
    if (size > 1) {
      all.resize(b * N * c);
      std::vector<int> counts(static_cast<std::size_t>(size)), displs(static_cast<std::size_t>(size));
      for (int r = 0, at = 0; r < size; ++r) {
        counts[r] = static_cast<int>(b * ranges[2 * r + 1] * c);
        displs[r] = at;
        at += counts[r];
      }
      std::vector<double> gathered(b * N * c);
      MPI_Allgatherv(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, gathered.data(), counts.data(),
                     displs.data(), MPI_DOUBLE, comm);
      for (int r = 0; r < size; ++r)  // rank r's block: b steps x its nodes x c
        for (std::size_t k = 0; k < b; ++k)
          std::copy_n(gathered.begin() + displs[r] + static_cast<std::ptrdiff_t>(k * ranges[2 * r + 1] * c),
                      ranges[2 * r + 1] * c, all.begin() + static_cast<std::ptrdiff_t>((k * N + ranges[2 * r]) * c));
    } else {
      all = std::move(mine);
    }
    const detail::ViewCopies copies(N, c, what);
    for (std::size_t k = 0; k < b; ++k) copies.create(view_groups[v].get(), flushed + k, all.data() + k * N * c);
  }
  compute_load_points(b);
  flush_file();
  // 3. only now are the steps announced to readers.
  flushed = steps;
  detail::write_int_attribute(file.get(), "steps_written", static_cast<std::int64_t>(flushed));
  flush_file();
  pend_time.clear();
  pend_sigma.clear();
  for (auto& p : pend_probe) p.clear();
  for (auto& f : pend_field) f.clear();
  last_flush = Clock::now();
}

void Writer::Impl::write_xdmf_text() {
  detail::XdmfModel m;
  m.h5_name = detail::sidecar_h5_name(path);
  m.nodes = nodes.global_count;
  m.times.assign(times.begin(), times.begin() + static_cast<std::ptrdiff_t>(flushed));
  m.arrays = plan.views;
  m.geometry = plan.geometry;
  m.loads = moving_loads;
  m.sigma = sigma_all;
  m.load_values = load_values_all;
  detail::write_xdmf_file(xmf_path, m);
}

// Rank 0 writes the sidecar of the flushed steps; every rank learns whether that worked.
void Writer::Impl::write_xdmf() {
  std::string error;
  if (rank == 0) {
    const auto t0 = Clock::now();
    try {
      write_xdmf_text();
    } catch (const std::exception& e) {
      error = e.what();
      if (error.empty()) error = "cannot write " + xmf_path;
    }
    // While running, writing the sidecar takes at most about 5 % of the wall time.
    xdmf_wait = xdmf_seconds > 0.0 ? std::max(xdmf_seconds, 20.0 * seconds_since(t0)) : 0.0;
    last_xdmf = Clock::now();
  }
  agree(comm, error.empty(), error);
}

void Writer::Impl::close_all() noexcept {
  int finalized = 0;
  MPI_Finalized(&finalized);
  Handle* handles[] = {&time_ds, &sigma_ds, &probes_group, &fields_group, &xdmf_group};
  if (finalized) {
    // MPI_Finalize has shut HDF5 down; the identifiers are stale.
    for (Handle* h : handles) h->release();
    for (auto& p : probes) p.dataset.release();
    for (auto& f : fields) f.dataset.release();
    for (auto& g : view_groups) g.release();
    dxpl.release();
    file.release();
    comm = MPI_COMM_NULL;
    state = State::closed;
    return;
  }
  for (Handle* h : handles) h->reset();
  for (auto& p : probes) p.dataset.reset();
  for (auto& f : fields) f.dataset.reset();
  for (auto& g : view_groups) g.reset();
  dxpl.reset();
  if (file.valid() && H5Fflush(file.get(), H5F_SCOPE_LOCAL) >= 0) set_file_size(false);
  file.reset();
  if (comm != MPI_COMM_NULL) MPI_Comm_free(&comm);
  state = State::closed;
}

void Writer::Impl::check_layout(const NodeLayout& nodes, std::size_t moving_loads) {
  Impl& w = *this;
  // Arguments, then the node layout (all ranks see all ranges).
  std::string bad;
  if (moving_loads < 1) bad = "output: moving_loads must be at least 1";
  else if (nodes.global_count < 1) bad = "output: the structure needs at least one node";
  else if (nodes.s.size() != nodes.count)
    bad = "output: NodeLayout.s has " + std::to_string(nodes.s.size()) + " values for " +
          std::to_string(nodes.count) + " local nodes";
  else if (nodes.first + nodes.count > nodes.global_count)
    bad = "output: local node range exceeds the global node count";
  agree(w.comm, bad.empty(), bad);
  std::vector<unsigned long long> ranges(2 * static_cast<std::size_t>(w.size));
  const unsigned long long mine[2] = {nodes.first, nodes.count};
  par::allgather_bytes(mine, sizeof mine, ranges.data(), w.comm);
  std::vector<std::pair<unsigned long long, unsigned long long>> sorted;
  for (int r = 0; r < w.size; ++r)
    if (ranges[2 * r + 1] > 0) sorted.emplace_back(ranges[2 * r], ranges[2 * r + 1]);
  std::sort(sorted.begin(), sorted.end());
  unsigned long long next = 0;
  for (const auto& [first, count] : sorted) {
    if (first != next) {
      bad = "output: the ranks' node ranges do not tile 0.." +
            std::to_string(nodes.global_count - 1) + " (gap or overlap at node " +
            std::to_string(std::min(first, next)) + ")";
      break;
    }
    next = first + count;
  }
  if (bad.empty() && next != nodes.global_count)
    bad = "output: the ranks' node ranges cover " + std::to_string(next) + " of " +
          std::to_string(nodes.global_count) + " nodes";
  if (!bad.empty()) throw OutputError(bad);  // identical on all ranks
  w.ranges = ranges;
  // Neighbours along the structure (for the loads' positions): the owners of the nodes
  // just before and just after this rank's range.
  for (int r = 0; r < w.size && nodes.count > 0; ++r) {
    if (ranges[2 * r + 1] == 0) continue;
    if (ranges[2 * r] + ranges[2 * r + 1] == nodes.first) w.prev_owner = r;
    if (ranges[2 * r] == nodes.first + nodes.count) w.next_owner = r;
  }
}

void Writer::Impl::check_output_location(bool overwrite) {
  Impl& w = *this;
  const std::string& path = w.path;
  // The location: decided on rank 0, broadcast.
  std::string location_error;
  if (w.rank == 0) location_error = check_location(path, w.xmf_path, overwrite);
  unsigned long len = location_error.size();
  par::bcast(&len, 1, MPI_UNSIGNED_LONG, 0, w.comm);
  location_error.resize(len);
  par::bcast(location_error.data(), static_cast<int>(len), MPI_CHAR, 0, w.comm);
  if (!location_error.empty()) throw OutputError(location_error);
}

void Writer::Impl::create_file(bool overwrite) {
  Impl& w = *this;
  const std::string& path = w.path;
  // File access: MPI-IO with collective metadata (one rank, or a process without MPI: the
  // POSIX driver), dense attribute storage for long attributes such as the scene text.
  const bool posix = par::alone(w.comm);
  Handle fapl = detail::plist_handle(check_id(H5Pcreate(H5P_FILE_ACCESS), "H5Pcreate", path));
  if (posix) {
    check(H5Pset_fapl_sec2(fapl.get()), "H5Pset_fapl_sec2", path);
    // No file lock, as with MPI-IO: readers (which open without one, Reader) may open the
    // file while it is written, in this process too (HDF5 refuses a second open of a file
    // with other locking flags).
    check(H5Pset_file_locking(fapl.get(), 0, 1), "H5Pset_file_locking", path);
  } else {
    check(H5Pset_fapl_mpio(fapl.get(), w.comm, MPI_INFO_NULL), "H5Pset_fapl_mpio", path);
    check(H5Pset_all_coll_metadata_ops(fapl.get(), 1), "H5Pset_all_coll_metadata_ops", path);
    check(H5Pset_coll_metadata_write(fapl.get(), 1), "H5Pset_coll_metadata_write", path);
  }
  // Objects in the 1.8 format, except the sidecar's views (virtual datasets need 1.10).
  check(H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V18, H5F_LIBVER_V110),
        "H5Pset_libver_bounds", path);
  Handle fcpl = detail::plist_handle(check_id(H5Pcreate(H5P_FILE_CREATE), "H5Pcreate", path));
  check(H5Pset_attr_phase_change(fcpl.get(), 0, 0), "H5Pset_attr_phase_change", path);
  w.file = detail::file_handle(check_id(
      H5Fcreate(path.c_str(), overwrite ? H5F_ACC_TRUNC : H5F_ACC_EXCL, fcpl.get(), fapl.get()),
      "H5Fcreate", path));
  w.dxpl = detail::plist_handle(check_id(H5Pcreate(H5P_DATASET_XFER), "H5Pcreate", path));
  if (!posix) check(H5Pset_dxpl_mpio(w.dxpl.get(), H5FD_MPIO_COLLECTIVE), "H5Pset_dxpl_mpio", path);
}

void Writer::Impl::write_run_attributes(const RunInfo& info) {
  Impl& w = *this;
  const hid_t root = w.file.get();
  detail::write_string_attribute(root, "status", "running");
  detail::write_int_attribute(root, "steps_written", 0);
  detail::write_int_attribute(root, "traverse_output_format", file_format_version);
  detail::write_string_attribute(root, "traverse_version", info.version);
  detail::write_string_attribute(root, "command_line", info.command_line);
  detail::write_string_attribute(root, "scene", info.scene_text);
  detail::write_string_attribute(root, "scene_file", info.scene_file);
  detail::write_string_attribute(root, "model", info.model);
  for (const auto& [name, value] : info.attributes) detail::write_string_attribute(root, name, value);
}

void Writer::Impl::create_series(std::size_t moving_loads) {
  Impl& w = *this;
  const hid_t root = w.file.get();
  // /time, /sigma
  w.time_ds = create_extendible(root, "time", {}, {series_chunk_rows(1)});
  write_meta(w.time_ds.get(), "s", "simulated time of each output step");
  if (moving_loads == 1)
    w.sigma_ds = create_extendible(root, "sigma", {}, {series_chunk_rows(1)});
  else
    w.sigma_ds = create_extendible(root, "sigma", {moving_loads},
                                   {series_chunk_rows(moving_loads), moving_loads});
  write_meta(w.sigma_ds.get(), "m",
             "position of each moving load along the structure (arclength s)");
  if (moving_loads > 1)
    detail::write_string_attribute(w.sigma_ds.get(), "components",
                                   detail::join(default_component_names(moving_loads), ','));
}

void Writer::Impl::write_mesh() {
  Impl& w = *this;
  const hid_t root = w.file.get();
  const NodeLayout& nodes = w.nodes;
  // /mesh: arclength, reference positions ((s, 0, 0) for a beam, (0, 0, s) otherwise),
  // polyline segments.
  Handle mesh = create_group(root, "mesh");
  const hsize_t n = nodes.global_count;
  const bool has_local = nodes.count > 0;
  {
    Handle s = create_fixed(mesh.get(), "s", H5T_IEEE_F64LE, {n});
    write_meta(s.get(), "m", "arclength of the nodes along the undeformed structure");
    write_block(s.get(), w.dxpl.get(), H5T_NATIVE_DOUBLE, {nodes.first}, {nodes.count},
                nodes.s.data(), has_local, "/mesh/s");
  }
  {
    const bool beam = w.model == "beam";
    std::vector<double> xyz(3 * nodes.count, 0.0);
    for (std::size_t i = 0; i < nodes.count; ++i) xyz[3 * i + (beam ? 0 : 2)] = nodes.s[i];
    w.reference_xyz = xyz;
    Handle p = create_fixed(mesh.get(), "position", H5T_IEEE_F64LE, {n, 3});
    write_meta(p.get(), "m",
               std::string("reference node positions ") + (beam ? "(s, 0, 0)" : "(0, 0, s)") +
                   " used by the XDMF sidecar when no geometry field is written");
    detail::write_string_attribute(p.get(), "components", "x,y,z");
    write_block(p.get(), w.dxpl.get(), H5T_NATIVE_DOUBLE, {nodes.first, 0}, {nodes.count, 3},
                xyz.data(), has_local, "/mesh/position");
  }
  {
    const std::size_t last_seg = static_cast<std::size_t>(n) - 1;  // segments 0..n-2
    const std::size_t seg_first = std::min(nodes.first, last_seg);
    const std::size_t seg_end = std::min(nodes.first + nodes.count, last_seg);
    std::vector<int> seg;
    for (std::size_t i = seg_first; i < seg_end; ++i) {
      seg.push_back(static_cast<int>(i));
      seg.push_back(static_cast<int>(i + 1));
    }
    Handle g = create_fixed(mesh.get(), "segments", H5T_STD_I32LE, {n - 1, 2});
    detail::write_string_attribute(g.get(), "description",
                                   "node pairs (i, i+1) of the polyline, for the XDMF sidecar");
    write_block(g.get(), w.dxpl.get(), H5T_NATIVE_INT, {seg_first, 0}, {seg_end - seg_first, 2},
                seg.data(), seg_end > seg_first, "/mesh/segments");
  }
  // The arclength of the node after this rank's last one (for the loads' positions).
  {
    const double first_s = nodes.count > 0 ? nodes.s.front() : 0.0;
    if (!par::alone(w.comm))
      MPI_Sendrecv(&first_s, 1, MPI_DOUBLE, nodes.count > 0 ? w.prev_owner : MPI_PROC_NULL, 7100, &w.halo_s, 1,
                   MPI_DOUBLE, nodes.count > 0 ? w.next_owner : MPI_PROC_NULL, 7100, w.comm, MPI_STATUS_IGNORE);
  }
}

void Writer::Impl::create_groups() {
  Impl& w = *this;
  const hid_t root = w.file.get();
  w.probes_group = create_group(root, "probes");
  w.fields_group = create_group(root, "fields");
  w.xdmf_group = create_group(root, "xdmf");
  detail::write_string_attribute(
      w.xdmf_group.get(), "description",
      "one virtual dataset per node array and output step for the XDMF sidecar: "
      "/xdmf/<array>/<step> maps step <step> of /fields/<field> (see the group attributes)");
  detail::write_string_attribute(w.xdmf_group.get(), "arrays", "");
  detail::write_string_attribute(w.xdmf_group.get(), "geometry", "");
}

Writer::Writer(MPI_Comm comm, const std::string& path, bool overwrite, const RunInfo& info,
               const NodeLayout& nodes, std::size_t moving_loads)
    : impl_(std::make_unique<Impl>()) {
  detail::silence_hdf5_errors();
  Impl& w = *impl_;
  // MPI_COMM_NULL: this process alone, without MPI. A communicator of one rank is written
  // the same way (the POSIX driver, no MPI calls): MPI-IO's collective machinery buys
  // nothing for one writer.
  if (!par::alone(comm)) {
    int initialized = 0;
    MPI_Initialized(&initialized);
    if (!initialized) throw OutputError("traverse::output::Writer needs MPI to be initialised for a communicator");
    if (par::size(comm) > 1 && MPI_Comm_dup(comm, &w.comm) != MPI_SUCCESS)
      throw OutputError("output: MPI_Comm_dup failed for " + path);
  }
  w.rank = par::rank(w.comm);
  w.size = par::size(w.comm);
  w.path = path;
  w.xmf_path = sidecar_path(path);
  w.nodes = nodes;
  w.moving_loads = moving_loads;
  w.model = info.model;
  try {
    w.check_layout(nodes, moving_loads);
    w.check_output_location(overwrite);
    w.create_file(overwrite);
    w.write_run_attributes(info);
    w.create_series(moving_loads);
    w.write_mesh();
    w.create_groups();
    w.flush_file();
    w.write_xdmf();
  } catch (...) {
    w.close_all();
    throw;
  }
}

Writer::~Writer() {
  if (!impl_) return;
  try {
    int finalized = 0;
    MPI_Finalized(&finalized);
    if (!finalized && impl_->state == State::running && impl_->file.valid()) {
      impl_->flush_pending();
      if (impl_->rank == 0) {
        try {
          impl_->write_xdmf_text();
        } catch (...) {
        }
      }
      impl_->set_status("failed: output closed before finish() or fail()");
    }
  } catch (...) {
  }
  impl_->close_all();
}

Writer::Writer(Writer&&) noexcept = default;
Writer& Writer::operator=(Writer&& other) noexcept {
  if (this != &other) {
    Writer old(std::move(*this));  // closes the current file, if any
    impl_ = std::move(other.impl_);
  }
  return *this;
}

namespace {

// What is wrong with a probe's or field's declaration (`kind` "probe" or "field"), or "".
std::string declaration_problem(const char* kind, bool started, const std::string& name, std::size_t components,
                                const std::vector<std::string>& component_names) {
  const std::string k(kind);
  if (started) return "output: " + k + " '" + name + "' added after the first output step";
  if (!detail::valid_name(name))
    return "output: invalid " + k + " name '" + name + "' (use letters, digits, '_', '.', '-')";
  if (components < 1) return "output: " + k + " '" + name + "' needs at least one component";
  if (!component_names.empty() && component_names.size() != components)
    return "output: " + k + " '" + name + "' has " + std::to_string(component_names.size()) + " component names for " +
           std::to_string(components) + " components";
  for (const auto& c : component_names)
    if (!detail::valid_name(c)) return "output: invalid component name '" + c + "' of " + k + " '" + name + "'";
  return "";
}

}  // namespace

std::size_t Writer::add_probe(const ProbeSpec& spec) {
  Impl& w = *impl_;
  w.require_open("add_probe");
  std::string bad = declaration_problem("probe", w.steps > 0 || w.state != State::running, spec.name, spec.components,
                                        spec.component_names);
  for (const auto& p : w.probes)
    if (bad.empty() && p.name == spec.name) bad = "output: duplicate probe '" + spec.name + "'";
  if (!bad.empty()) throw OutputError(bad);  // replicated arguments: all ranks agree

  Series1 p;
  p.name = spec.name;
  p.components = spec.components;
  p.matrix = spec.components > 1;
  const std::string what = "/probes/" + spec.name;
  if (p.matrix)
    p.dataset = create_extendible(w.probes_group.get(), spec.name, {spec.components},
                                  {series_chunk_rows(spec.components), spec.components});
  else
    p.dataset = create_extendible(w.probes_group.get(), spec.name, {}, {series_chunk_rows(1)});
  write_meta(p.dataset.get(), spec.units, spec.description);
  if (!spec.component_names.empty())
    detail::write_string_attribute(p.dataset.get(), "components",
                                   detail::join(spec.component_names, ','));
  w.probes.push_back(std::move(p));
  w.pend_probe.emplace_back();
  return w.probes.size() - 1;
}

std::size_t Writer::add_field(const FieldSpec& spec) {
  Impl& w = *impl_;
  w.require_open("add_field");
  std::string bad = declaration_problem("field", w.steps > 0 || w.state != State::running, spec.name, spec.components,
                                        spec.component_names);
  if (bad.empty() && spec.geometry && spec.components != 3)
    bad = "output: geometry field '" + spec.name + "' must have 3 components (x, y, z)";
  for (const auto& f : w.fields) {
    if (bad.empty() && f.spec.name == spec.name) bad = "output: duplicate field '" + spec.name + "'";
    if (bad.empty() && f.spec.geometry && spec.geometry)
      bad = "output: two geometry fields ('" + f.spec.name + "', '" + spec.name + "')";
  }
  if (!bad.empty()) throw OutputError(bad);

  Field1 f;
  f.spec = spec;
  if (f.spec.component_names.empty()) f.spec.component_names = default_component_names(spec.components);
  const hsize_t n = w.nodes.global_count;
  // Chunks of whole steps (a step is read or written at once), as many steps as fit in
  // 64 KiB; a step larger than that is split into chunks of up to 64 Ki values.
  const hsize_t step_values = n * static_cast<hsize_t>(spec.components);
  const hsize_t node_chunk =
      std::min<hsize_t>(n, std::max<hsize_t>(1, 65536 / static_cast<hsize_t>(spec.components)));
  const hsize_t step_chunk = node_chunk < n ? 1 : std::max<hsize_t>(1, 8192 / std::max<hsize_t>(1, step_values));
  f.dataset = create_extendible(w.fields_group.get(), spec.name, {n, spec.components},
                                {step_chunk, node_chunk, spec.components});
  write_meta(f.dataset.get(), spec.units, spec.description);
  detail::write_string_attribute(f.dataset.get(), "components",
                                 detail::join(f.spec.component_names, ','));
  if (spec.geometry) detail::write_int_attribute(f.dataset.get(), "geometry", 1);
  w.fields.push_back(std::move(f));
  w.pend_field.emplace_back();
  w.field_bytes_per_step += sizeof(double) * static_cast<std::size_t>(n) * spec.components;

  // The sidecar's arrays: planned again over all fields (a later field may take the
  // geometry), their groups created or re-labelled.
  std::vector<detail::XdmfFieldInfo> infos;
  for (const Field1& g : w.fields)
    infos.push_back({g.spec.name, g.spec.components, g.spec.component_names, g.spec.geometry, g.spec.sidecar});
  w.plan = detail::plan_views(infos);
  for (Handle& g : w.view_groups) g.reset();
  w.view_groups.clear();
  for (const std::string& old : detail::link_names(w.xdmf_group.get(), "/xdmf"))
    check(H5Ldelete(w.xdmf_group.get(), old.c_str(), H5P_DEFAULT), "H5Ldelete", "/xdmf/" + old);
  std::vector<std::string> arrays;
  for (const detail::XdmfView& v : w.plan.views) {
    arrays.push_back(v.array);
    Handle g = create_group(w.xdmf_group.get(), v.array);
    detail::write_string_attribute(g.get(), "field", w.fields[v.field].spec.name);
    detail::write_int_attribute(g.get(), "first_component", static_cast<std::int64_t>(v.first));
    detail::write_int_attribute(g.get(), "components", static_cast<std::int64_t>(v.count));
    w.view_groups.push_back(std::move(g));
  }
  detail::write_string_attribute(w.xdmf_group.get(), "arrays", detail::join(arrays, ','));
  detail::write_string_attribute(
      w.xdmf_group.get(), "geometry",
      w.plan.geometry >= 0 ? w.plan.views[static_cast<std::size_t>(w.plan.geometry)].array : std::string());
  return w.fields.size() - 1;
}

void Writer::write_step(double time, const std::vector<double>& sigma,
                        const std::vector<std::vector<double>>& probes,
                        const std::vector<DoubleView>& fields) {
  Impl& w = *impl_;
  w.require_open("write_step");
  std::string bad;
  if (w.state != State::running)
    bad = "output: write_step after finish() or fail() on " + w.path;
  else if (sigma.size() != w.moving_loads)
    bad = "output: write_step got " + std::to_string(sigma.size()) + " load positions for " +
          std::to_string(w.moving_loads) + " moving loads";
  else if (probes.size() != w.probes.size())
    bad = "output: write_step got " + std::to_string(probes.size()) + " probe values for " +
          std::to_string(w.probes.size()) + " probes";
  else if (fields.size() != w.fields.size())
    bad = "output: write_step got " + std::to_string(fields.size()) + " fields for " +
          std::to_string(w.fields.size()) + " declared fields";
  for (std::size_t i = 0; bad.empty() && i < probes.size(); ++i)
    if (probes[i].size() != w.probes[i].components)
      bad = "output: probe '" + w.probes[i].name + "' got " + std::to_string(probes[i].size()) +
            " values for " + std::to_string(w.probes[i].components) + " components";
  for (std::size_t j = 0; bad.empty() && j < fields.size(); ++j) {
    const std::size_t want = w.nodes.count * w.fields[j].spec.components;
    if (fields[j].size != want || (want > 0 && fields[j].data == nullptr))
      bad = "output: field '" + w.fields[j].spec.name + "' got " + std::to_string(fields[j].size) +
            " values on rank " + std::to_string(w.rank) + ", expected " + std::to_string(want) +
            " (local nodes x components)";
  }
  agree(w.comm, bad.empty(), bad);

  // Kept in memory until the next flush.
  w.pend_time.push_back(time);
  w.pend_sigma.insert(w.pend_sigma.end(), sigma.begin(), sigma.end());
  for (std::size_t i = 0; i < probes.size(); ++i)
    w.pend_probe[i].insert(w.pend_probe[i].end(), probes[i].begin(), probes[i].end());
  for (std::size_t j = 0; j < fields.size(); ++j)
    w.pend_field[j].insert(w.pend_field[j].end(), fields[j].data, fields[j].data + fields[j].size);
  ++w.steps;
  w.times.push_back(time);

  // Flush (and the sidecar) when due: rank 0's clock decides for all ranks; the memory
  // bound is the same on every rank.
  int due = 0;
  if (w.rank == 0) {
    if (seconds_since(w.last_flush) >= w.flush_seconds) due |= 1;
    if (seconds_since(w.last_xdmf) >= w.xdmf_wait) due |= 3;
  }
  if (w.size > 1) MPI_Bcast(&due, 1, MPI_INT, 0, w.comm);
  if ((w.steps - w.flushed) * w.field_bytes_per_step >= max_pending_bytes) due |= 1;
  if (due & 1) w.flush_pending();
  if (due & 2) w.write_xdmf();
}

void Writer::flush() {
  Impl& w = *impl_;
  w.require_open("flush");
  w.flush_pending();
}

void Writer::set_intervals(double flush_seconds, double xdmf_seconds) {
  Impl& w = *impl_;
  if (!(flush_seconds >= 0.0) || !(xdmf_seconds >= 0.0))
    throw OutputError("output: set_intervals needs intervals >= 0 s");
  w.flush_seconds = flush_seconds;
  w.xdmf_seconds = xdmf_seconds;
  w.xdmf_wait = xdmf_seconds;
}

double Writer::flush_interval() const { return impl_->flush_seconds; }
double Writer::xdmf_interval() const { return impl_->xdmf_seconds; }

void Writer::write_restart(double time, const std::vector<RestartArray>& arrays) {
  Impl& w = *impl_;
  w.require_open("write_restart");
  std::string bad;
  std::vector<std::string> names;
  for (const auto& a : arrays) {
    if (!bad.empty()) break;
    if (!detail::valid_name(a.name)) bad = "output: invalid restart array name '" + a.name + "'";
    else if (std::find(names.begin(), names.end(), a.name) != names.end())
      bad = "output: duplicate restart array '" + a.name + "'";
    else if (a.distribution == RestartDistribution::per_node &&
             (a.components < 1 || a.data.size != w.nodes.count * a.components))
      bad = "output: restart array '" + a.name + "' has " + std::to_string(a.data.size) +
            " values on rank " + std::to_string(w.rank) + ", expected local nodes x components = " +
            std::to_string(w.nodes.count * a.components);
    names.push_back(a.name);
  }
  agree(w.comm, bad.empty(), bad);
  unsigned long long count0 = arrays.size();
  par::bcast(&count0, 1, MPI_UNSIGNED_LONG_LONG, 0, w.comm);
  agree(w.comm, count0 == arrays.size(),
        "output: write_restart got " + std::to_string(arrays.size()) + " arrays on rank " +
            std::to_string(w.rank) + " but " + std::to_string(count0) + " on rank 0");
  // Replicated sizes must agree (rank 0's are written).
  std::vector<unsigned long long> sizes;
  for (const auto& a : arrays) sizes.push_back(a.data.size);
  std::vector<unsigned long long> sizes0 = sizes;
  if (!sizes0.empty())
    par::bcast(sizes0.data(), static_cast<int>(sizes0.size()), MPI_UNSIGNED_LONG_LONG, 0, w.comm);
  for (std::size_t i = 0; bad.empty() && i < arrays.size(); ++i)
    if (arrays[i].distribution == RestartDistribution::replicated && sizes[i] != sizes0[i])
      bad = "output: replicated restart array '" + arrays[i].name + "' has " +
            std::to_string(sizes[i]) + " values on rank " + std::to_string(w.rank) + " but " +
            std::to_string(sizes0[i]) + " on rank 0";
  agree(w.comm, bad.empty(), bad);

  w.flush_pending();  // the restart point refers to steps in the file
  const hid_t root = w.file.get();
  const htri_t exists = H5Lexists(root, "restart", H5P_DEFAULT);
  check(exists, "H5Lexists", "/restart");
  Handle group = exists > 0 ? detail::group_handle(check_id(H5Gopen2(root, "restart", H5P_DEFAULT),
                                                            "H5Gopen2", "/restart"))
                            : create_group(root, "restart");
  detail::write_int_attribute(group.get(), "valid", 0);
  w.flush_file();
  // Remove arrays of earlier calls that are not repeated or changed shape; keep the others.
  for (const std::string& old : detail::link_names(group.get(), "/restart")) {
    bool keep = false;
    for (const auto& a : arrays) {
      if (a.name != old) continue;
      Handle d = detail::dataset_handle(
          check_id(H5Dopen2(group.get(), old.c_str(), H5P_DEFAULT), "H5Dopen2", "/restart/" + old));
      std::vector<hsize_t> want;
      if (a.distribution == RestartDistribution::per_node) {
        want.push_back(w.nodes.global_count);
        if (a.components > 1) want.push_back(a.components);
      } else {
        want.push_back(a.data.size);
      }
      keep = detail::dataset_dims(d.get(), "/restart/" + old) == want;
    }
    if (!keep) check(H5Ldelete(group.get(), old.c_str(), H5P_DEFAULT), "H5Ldelete", "/restart/" + old);
  }
  for (const auto& a : arrays) {
    const std::string what = "/restart/" + a.name;
    const htri_t have = H5Lexists(group.get(), a.name.c_str(), H5P_DEFAULT);
    check(have, "H5Lexists", what);
    const bool per_node = a.distribution == RestartDistribution::per_node;
    std::vector<hsize_t> dims;
    if (per_node) {
      dims.push_back(w.nodes.global_count);
      if (a.components > 1) dims.push_back(a.components);
    } else {
      dims.push_back(a.data.size);
    }
    Handle d = have > 0 ? detail::dataset_handle(check_id(
                              H5Dopen2(group.get(), a.name.c_str(), H5P_DEFAULT), "H5Dopen2", what))
                        : create_fixed(group.get(), a.name, H5T_IEEE_F64LE, dims);
    detail::write_string_attribute(d.get(), "distribution", per_node ? "per_node" : "replicated");
    if (per_node) {
      std::vector<hsize_t> start{w.nodes.first}, count{w.nodes.count};
      if (a.components > 1) {
        start.push_back(0);
        count.push_back(a.components);
      }
      write_block(d.get(), w.dxpl.get(), H5T_NATIVE_DOUBLE, start, count, a.data.data,
                  w.nodes.count > 0, what);
    } else {
      write_block(d.get(), w.dxpl.get(), H5T_NATIVE_DOUBLE, {0}, {a.data.size}, a.data.data,
                  w.rank == 0, what);
    }
  }
  w.flush_file();
  detail::write_double_attribute(group.get(), "time", time);
  detail::write_int_attribute(group.get(), "steps_written", static_cast<std::int64_t>(w.flushed));
  detail::write_int_attribute(group.get(), "valid", 1);
  w.flush_file();
}

void Writer::write_events(const std::vector<RunEvent>& events) {
  Impl& w = *impl_;
  w.require_open("write_events");
  const hid_t root = w.file.get();
  const htri_t exists = H5Lexists(root, "events", H5P_DEFAULT);
  check(exists, "H5Lexists", "/events");
  if (exists > 0) check(H5Ldelete(root, "events", H5P_DEFAULT), "H5Ldelete", "/events");
  Handle group = create_group(root, "events");
  const hsize_t n = events.size();
  std::vector<double> time, position;
  std::vector<std::string> loads, reasons;
  for (const auto& e : events) {
    time.push_back(e.time);
    position.push_back(e.position);
    loads.push_back(e.load);
    reasons.push_back(e.reason);
  }
  detail::write_int_attribute(group.get(), "count", static_cast<std::int64_t>(n));
  detail::write_string_attribute(group.get(), "loads", detail::join(loads, ','));
  detail::write_string_attribute(group.get(), "reasons", detail::join(reasons, ','));
  if (n > 0) {
    const std::pair<const char*, const std::vector<double>*> columns[] = {{"time", &time}, {"position", &position}};
    for (const auto& [name, values] : columns) {
      Handle d = create_fixed(group.get(), name, H5T_IEEE_F64LE, {n});
      write_block(d.get(), w.dxpl.get(), H5T_NATIVE_DOUBLE, {0}, {n}, values->data(), w.rank == 0,
                  std::string("/events/") + name);
    }
  }
  detail::write_string_attribute(root, "end_reason", events.empty() ? "end_time" : events.front().reason);
  w.flush_file();
}

void Writer::write_probe_extremes(std::size_t probe, const ProbeExtremes& e) {
  Impl& w = *impl_;
  w.require_open("write_probe_extremes");
  if (probe >= w.probes.size()) throw OutputError("output: write_probe_extremes of an undeclared probe");
  const Series1& p = w.probes[probe];
  const std::string what = "/probes/" + p.name;
  for (const auto* v : {&e.min, &e.max, &e.time_of_min, &e.time_of_max})
    if (v->size() != p.components) throw OutputError("output: " + what + ": extremes need one value per component");
  const hid_t d = p.dataset.get();
  detail::write_double_array_attribute(d, "min", e.min);
  detail::write_double_array_attribute(d, "max", e.max);
  detail::write_double_array_attribute(d, "time_of_min", e.time_of_min);
  detail::write_double_array_attribute(d, "time_of_max", e.time_of_max);
}

void Writer::set_attribute(const std::string& name, const std::string& value) {
  Impl& w = *impl_;
  w.require_open("set_attribute");
  detail::write_string_attribute(w.file.get(), name, value);
}

void Writer::finish() {
  Impl& w = *impl_;
  w.require_open("finish");
  if (w.state == State::failed)
    throw OutputError("output: finish() after fail() on " + w.path);
  w.flush_pending();
  w.write_xdmf();
  w.set_status("complete");
  w.state = State::finished;
}

void Writer::fail(const std::string& reason) {
  Impl& w = *impl_;
  w.require_open("fail");
  w.flush_pending();
  w.write_xdmf();
  w.set_status("failed: " + reason);
  w.state = State::failed;
}

std::size_t Writer::steps_written() const { return impl_->steps; }
std::size_t Writer::steps_flushed() const { return impl_->flushed; }
const std::string& Writer::path() const { return impl_->path; }
const std::string& Writer::xdmf_path() const { return impl_->xmf_path; }

}  // namespace traverse::output
