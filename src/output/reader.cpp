#include "traverse/output/reader.hpp"

#include <algorithm>

#include "hdf5_handle.hpp"

namespace traverse::output {

using detail::check;
using detail::check_id;
using detail::Handle;

struct Reader::Impl {
  std::string path;
  Handle file;

  Handle open_dataset(const std::string& name) const {
    const htri_t exists = H5Lexists(file.get(), name.c_str(), H5P_DEFAULT);
    if (exists <= 0) {
      H5Eclear2(H5E_DEFAULT);
      throw OutputError("output file " + path + " has no dataset " + name);
    }
    return detail::dataset_handle(
        check_id(H5Dopen2(file.get(), name.c_str(), H5P_DEFAULT), "H5Dopen2", path + ":" + name));
  }
  bool has_link(const std::string& name) const {
    const htri_t rc = H5Lexists(file.get(), name.c_str(), H5P_DEFAULT);
    if (rc < 0) H5Eclear2(H5E_DEFAULT);
    return rc > 0;
  }
  std::string optional_string(hid_t obj, const std::string& attr) const {
    return detail::has_attribute(obj, attr) ? detail::read_string_attribute(obj, attr)
                                            : std::string();
  }
  /// Reads rows [first, first+rows) of a dataset of rank 1..3 whose first dimension is the
  /// row index; for rank 3 (fields) `row_index` selects along the first dimension and the
  /// rows are taken along the second.
  std::vector<double> read_block(hid_t d, const std::vector<hsize_t>& start,
                                 const std::vector<hsize_t>& count, const std::string& what) const {
    Handle fspace = detail::space_handle(check_id(H5Dget_space(d), "H5Dget_space", what));
    hsize_t n = 1;
    for (hsize_t c : count) n *= c;
    std::vector<double> out(static_cast<std::size_t>(n));
    if (n == 0) return out;
    check(H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start.data(), nullptr, count.data(),
                              nullptr),
          "H5Sselect_hyperslab", what);
    // Memory space of the selection's shape (block-wise chunk mapping, see the Writer).
    Handle mspace = detail::space_handle(check_id(
        H5Screate_simple(static_cast<int>(count.size()), count.data(), nullptr), "H5Screate_simple", what));
    check(H5Dread(d, H5T_NATIVE_DOUBLE, mspace.get(), fspace.get(), H5P_DEFAULT, out.data()),
          "H5Dread", what);
    return out;
  }
  Series read_series(const std::string& name, std::size_t rows_wanted) const {
    Handle d = open_dataset(name);
    const auto dims = detail::dataset_dims(d.get(), path + ":" + name);
    if (dims.empty() || dims.size() > 2)
      throw OutputError(path + ":" + name + " is not a time series (rank " +
                        std::to_string(dims.size()) + ")");
    if (dims[0] < rows_wanted)
      throw OutputError(path + ":" + name + " has " + std::to_string(dims[0]) +
                        " rows, fewer than steps_written = " + std::to_string(rows_wanted));
    Series s;
    s.rows = rows_wanted;
    s.components = dims.size() == 2 ? static_cast<std::size_t>(dims[1]) : 1;
    std::vector<hsize_t> start(dims.size(), 0), count = dims;
    count[0] = rows_wanted;
    s.values = read_block(d.get(), start, count, path + ":" + name);
    s.units = optional_string(d.get(), "units");
    s.description = optional_string(d.get(), "description");
    s.component_names = detail::split(optional_string(d.get(), "components"), ',');
    return s;
  }
};

Reader::Reader(const std::string& path) : impl_(std::make_unique<Impl>()) {
  detail::silence_hdf5_errors();
  impl_->path = path;
  Handle fapl = detail::plist_handle(check_id(H5Pcreate(H5P_FILE_ACCESS), "H5Pcreate", path));
#if H5_VERSION_GE(1, 10, 7)
  // A file still being written (or left by a killed run) must be readable.
  check(H5Pset_file_locking(fapl.get(), 0, 1), "H5Pset_file_locking", path);
#endif
  impl_->file = detail::file_handle(
      check_id(H5Fopen(path.c_str(), H5F_ACC_RDONLY, fapl.get()), "H5Fopen", path));
}

Reader::~Reader() = default;
Reader::Reader(Reader&&) noexcept = default;
Reader& Reader::operator=(Reader&&) noexcept = default;

std::size_t Reader::steps_written() const {
  return static_cast<std::size_t>(detail::read_int_attribute(impl_->file.get(), "steps_written"));
}

std::string Reader::attribute(const std::string& name) const {
  if (!detail::has_attribute(impl_->file.get(), name))
    throw OutputError("output file " + impl_->path + " has no attribute " + name);
  return detail::read_string_attribute(impl_->file.get(), name);
}

bool Reader::has_attribute(const std::string& name) const {
  return detail::has_attribute(impl_->file.get(), name);
}

std::string Reader::status() const { return attribute("status"); }

std::vector<double> Reader::time() const {
  return impl_->read_series("/time", steps_written()).values;
}

Series Reader::sigma() const { return impl_->read_series("/sigma", steps_written()); }

std::size_t Reader::moving_loads() const {
  Handle d = impl_->open_dataset("/sigma");
  const auto dims = detail::dataset_dims(d.get(), "/sigma");
  return dims.size() == 2 ? static_cast<std::size_t>(dims[1]) : 1;
}

std::vector<double> Reader::arclength() const {
  Handle d = impl_->open_dataset("/mesh/s");
  const auto dims = detail::dataset_dims(d.get(), "/mesh/s");
  return impl_->read_block(d.get(), {0}, dims, "/mesh/s");
}

std::size_t Reader::node_count() const {
  Handle d = impl_->open_dataset("/mesh/s");
  return static_cast<std::size_t>(detail::dataset_dims(d.get(), "/mesh/s").at(0));
}

std::vector<RunEvent> Reader::events() const {
  if (!impl_->has_link("/events")) return {};
  Handle g = detail::group_handle(check_id(H5Gopen2(impl_->file.get(), "events", H5P_DEFAULT), "H5Gopen2",
                                           impl_->path + ":/events"));
  const auto n = static_cast<std::size_t>(detail::read_int_attribute(g.get(), "count"));
  if (n == 0) return {};
  const auto loads = detail::split(detail::read_string_attribute(g.get(), "loads"), ',');
  const auto reasons = detail::split(detail::read_string_attribute(g.get(), "reasons"), ',');
  Handle dt = impl_->open_dataset("/events/time"), dp = impl_->open_dataset("/events/position");
  const auto time = impl_->read_block(dt.get(), {0}, {n}, "/events/time");
  const auto position = impl_->read_block(dp.get(), {0}, {n}, "/events/position");
  if (loads.size() != n || reasons.size() != n)
    throw OutputError("output file " + impl_->path + ": /events holds " + std::to_string(n) + " events but " +
                      std::to_string(loads.size()) + " load names and " + std::to_string(reasons.size()) + " reasons");
  std::vector<RunEvent> out;
  for (std::size_t i = 0; i < n; ++i) out.push_back({time[i], position[i], loads[i], reasons[i]});
  return out;
}

std::vector<std::string> Reader::probe_names() const {
  if (!impl_->has_link("/probes")) return {};
  Handle g = detail::group_handle(
      check_id(H5Gopen2(impl_->file.get(), "/probes", H5P_DEFAULT), "H5Gopen2", "/probes"));
  return detail::link_names(g.get(), "/probes");
}

Series Reader::probe(const std::string& name) const {
  return impl_->read_series("/probes/" + name, steps_written());
}

std::optional<ProbeExtremes> Reader::probe_extremes(const std::string& name) const {
  const std::string what = "/probes/" + name;
  Handle d = impl_->open_dataset(what);
  for (const char* a : {"min", "max", "time_of_min", "time_of_max"})
    if (!detail::has_attribute(d.get(), a)) return std::nullopt;
  ProbeExtremes e;
  e.min = detail::read_double_array_attribute(d.get(), "min");
  e.max = detail::read_double_array_attribute(d.get(), "max");
  e.time_of_min = detail::read_double_array_attribute(d.get(), "time_of_min");
  e.time_of_max = detail::read_double_array_attribute(d.get(), "time_of_max");
  return e;
}

std::vector<std::string> Reader::field_names() const {
  if (!impl_->has_link("/fields")) return {};
  Handle g = detail::group_handle(
      check_id(H5Gopen2(impl_->file.get(), "/fields", H5P_DEFAULT), "H5Gopen2", "/fields"));
  return detail::link_names(g.get(), "/fields");
}

Series Reader::field_info(const std::string& name) const {
  const std::string what = "/fields/" + name;
  Handle d = impl_->open_dataset(what);
  const auto dims = detail::dataset_dims(d.get(), what);
  if (dims.size() != 3) throw OutputError(impl_->path + ":" + what + " is not a field");
  Series s;
  s.rows = static_cast<std::size_t>(dims[1]);
  s.components = static_cast<std::size_t>(dims[2]);
  s.units = impl_->optional_string(d.get(), "units");
  s.description = impl_->optional_string(d.get(), "description");
  s.component_names = detail::split(impl_->optional_string(d.get(), "components"), ',');
  return s;
}

std::vector<double> Reader::field(const std::string& name, std::size_t step, std::size_t first,
                                  std::size_t count) const {
  const std::string what = "/fields/" + name;
  const std::size_t written = steps_written();
  if (step >= written)
    throw OutputError(impl_->path + ":" + what + ": step " + std::to_string(step) +
                      " not written (steps_written = " + std::to_string(written) + ")");
  Handle d = impl_->open_dataset(what);
  const auto dims = detail::dataset_dims(d.get(), what);
  if (dims.size() != 3 || dims[0] <= step)
    throw OutputError(impl_->path + ":" + what + " is not a field with step " +
                      std::to_string(step));
  const std::size_t nodes = static_cast<std::size_t>(dims[1]);
  if (first > nodes) throw OutputError(impl_->path + ":" + what + ": first node out of range");
  count = std::min(count, nodes - first);
  return impl_->read_block(d.get(), {step, first, 0}, {1, count, dims[2]}, what);
}

bool Reader::has_restart() const {
  if (!impl_->has_link("/restart")) return false;
  Handle g = detail::group_handle(
      check_id(H5Gopen2(impl_->file.get(), "/restart", H5P_DEFAULT), "H5Gopen2", "/restart"));
  return detail::has_attribute(g.get(), "valid") && detail::read_int_attribute(g.get(), "valid") == 1;
}

double Reader::restart_time() const {
  Handle g = detail::group_handle(
      check_id(H5Gopen2(impl_->file.get(), "/restart", H5P_DEFAULT), "H5Gopen2", "/restart"));
  return detail::read_double_attribute(g.get(), "time");
}

std::size_t Reader::restart_step() const {
  Handle g = detail::group_handle(
      check_id(H5Gopen2(impl_->file.get(), "/restart", H5P_DEFAULT), "H5Gopen2", "/restart"));
  return static_cast<std::size_t>(detail::read_int_attribute(g.get(), "steps_written"));
}

std::vector<std::string> Reader::restart_names() const {
  if (!impl_->has_link("/restart")) return {};
  Handle g = detail::group_handle(
      check_id(H5Gopen2(impl_->file.get(), "/restart", H5P_DEFAULT), "H5Gopen2", "/restart"));
  return detail::link_names(g.get(), "/restart");
}

Series Reader::restart(const std::string& name, std::size_t first, std::size_t count) const {
  const std::string what = "/restart/" + name;
  Handle d = impl_->open_dataset(what);
  const auto dims = detail::dataset_dims(d.get(), what);
  if (dims.empty() || dims.size() > 2) throw OutputError(impl_->path + ":" + what + ": bad rank");
  const bool per_node = impl_->optional_string(d.get(), "distribution") == "per_node";
  const std::size_t rows = static_cast<std::size_t>(dims[0]);
  if (!per_node) {
    first = 0;
    count = rows;
  }
  if (first > rows) throw OutputError(impl_->path + ":" + what + ": first row out of range");
  count = std::min(count, rows - first);
  Series s;
  s.rows = count;
  s.components = dims.size() == 2 ? static_cast<std::size_t>(dims[1]) : 1;
  std::vector<hsize_t> start{first}, cnt{count};
  if (dims.size() == 2) {
    start.push_back(0);
    cnt.push_back(dims[1]);
  }
  s.values = impl_->read_block(d.get(), start, cnt, what);
  s.description = impl_->optional_string(d.get(), "distribution");
  return s;
}

}  // namespace traverse::output
