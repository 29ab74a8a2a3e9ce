#include "traverse/output/sidecar.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "hdf5_handle.hpp"
#include "xdmf.hpp"

namespace traverse::output {

using detail::check;
using detail::check_id;
using detail::Handle;

namespace {

namespace fs = std::filesystem;

Handle open_file(const std::string& path, bool write) {
  Handle fapl = detail::plist_handle(check_id(H5Pcreate(H5P_FILE_ACCESS), "H5Pcreate", path));
#if H5_VERSION_GE(1, 10, 7)
  check(H5Pset_file_locking(fapl.get(), 0, 1), "H5Pset_file_locking", path);
#endif
  if (write)
    check(H5Pset_libver_bounds(fapl.get(), H5F_LIBVER_V18, H5F_LIBVER_V110), "H5Pset_libver_bounds", path);
  return detail::file_handle(
      check_id(H5Fopen(path.c_str(), write ? H5F_ACC_RDWR : H5F_ACC_RDONLY, fapl.get()), "H5Fopen", path));
}

bool has_link(hid_t loc, const std::string& name) {
  const htri_t rc = H5Lexists(loc, name.c_str(), H5P_DEFAULT);
  if (rc < 0) H5Eclear2(H5E_DEFAULT);
  return rc > 0;
}

Handle open_dataset(hid_t file, const std::string& name, const std::string& path) {
  if (!has_link(file, name)) throw OutputError(path + " has no dataset " + name + " (not a traverse output file?)");
  return detail::dataset_handle(check_id(H5Dopen2(file, name.c_str(), H5P_DEFAULT), "H5Dopen2", path + ":" + name));
}

/// Reads `count` x (the other extents) doubles of `dataset` from row `first` on.
std::vector<double> read_rows(hid_t d, hsize_t first, hsize_t count, const std::string& what) {
  std::vector<hsize_t> dims = detail::dataset_dims(d, what);
  if (dims.empty() || dims[0] < first + count) throw OutputError(what + " has fewer rows than steps_written");
  std::vector<hsize_t> start(dims.size(), 0);
  start[0] = first;
  dims[0] = count;
  hsize_t n = 1;
  for (hsize_t x : dims) n *= x;
  std::vector<double> out(static_cast<std::size_t>(n));
  if (n == 0) return out;
  Handle fspace = detail::space_handle(check_id(H5Dget_space(d), "H5Dget_space", what));
  check(H5Sselect_hyperslab(fspace.get(), H5S_SELECT_SET, start.data(), nullptr, dims.data(), nullptr),
        "H5Sselect_hyperslab", what);
  Handle mspace = detail::space_handle(
      check_id(H5Screate_simple(static_cast<int>(dims.size()), dims.data(), nullptr), "H5Screate_simple", what));
  check(H5Dread(d, H5T_NATIVE_DOUBLE, mspace.get(), fspace.get(), H5P_DEFAULT, out.data()), "H5Dread", what);
  return out;
}

}  // namespace

namespace {

// The fields of the file (3-dimensional /fields/* datasets) in name order.
std::vector<detail::XdmfFieldInfo> read_fields(hid_t f, const std::string& h5_path) {
  std::vector<detail::XdmfFieldInfo> fields;
  if (!has_link(f, "fields")) return fields;
  Handle g = detail::group_handle(check_id(H5Gopen2(f, "fields", H5P_DEFAULT), "H5Gopen2", "/fields"));
  for (const std::string& name : detail::link_names(g.get(), "/fields")) {
    Handle d = open_dataset(f, "/fields/" + name, h5_path);
    const auto dims = detail::dataset_dims(d.get(), "/fields/" + name);
    if (dims.size() != 3) continue;
    detail::XdmfFieldInfo fi;
    fi.name = name;
    fi.components = static_cast<std::size_t>(dims[2]);
    if (detail::has_attribute(d.get(), "components"))
      fi.component_names = detail::split(detail::read_string_attribute(d.get(), "components"), ',');
    fi.geometry = detail::has_attribute(d.get(), "geometry") && detail::read_int_attribute(d.get(), "geometry") == 1;
    fields.push_back(fi);
  }
  return fields;
}

// The views as the Writer recorded them in /xdmf, else (older files) planned from the fields.
detail::XdmfPlan view_plan(hid_t f, const std::vector<detail::XdmfFieldInfo>& fields, const std::string& h5_path) {
  auto field_index = [&](const std::string& name) -> std::size_t {
    for (std::size_t i = 0; i < fields.size(); ++i)
      if (fields[i].name == name) return i;
    throw OutputError(h5_path + ": /xdmf refers to a field " + name + " that /fields does not hold");
  };
  if (!has_link(f, "xdmf")) return detail::plan_views(fields);
  Handle x = detail::group_handle(check_id(H5Gopen2(f, "xdmf", H5P_DEFAULT), "H5Gopen2", "/xdmf"));
  if (!detail::has_attribute(x.get(), "arrays")) return detail::plan_views(fields);
  detail::XdmfPlan plan;
  const std::string geometry =
      detail::has_attribute(x.get(), "geometry") ? detail::read_string_attribute(x.get(), "geometry") : "";
  for (const std::string& a : detail::split(detail::read_string_attribute(x.get(), "arrays"), ',')) {
    Handle g = detail::group_handle(check_id(H5Gopen2(x.get(), a.c_str(), H5P_DEFAULT), "H5Gopen2", "/xdmf/" + a));
    detail::XdmfView v;
    v.array = a;
    v.field = field_index(detail::read_string_attribute(g.get(), "field"));
    v.first = static_cast<std::size_t>(detail::read_int_attribute(g.get(), "first_component"));
    v.count = static_cast<std::size_t>(detail::read_int_attribute(g.get(), "components"));
    if (a == geometry) plan.geometry = static_cast<int>(plan.views.size());
    plan.views.push_back(v);
  }
  return plan;
}

// Adds the views missing for some step (an older file) to the file, opened for writing.
std::size_t add_missing_views(const std::string& h5_path, const std::vector<detail::XdmfFieldInfo>& fields,
                              const detail::XdmfPlan& plan, std::size_t n, std::size_t steps) {
  std::size_t created = 0;
  Handle w = open_file(h5_path, true);
  auto ensure_group = [&](hid_t loc, const std::string& name) {
    if (has_link(loc, name))
      return detail::group_handle(check_id(H5Gopen2(loc, name.c_str(), H5P_DEFAULT), "H5Gopen2", name));
    return detail::group_handle(
        check_id(H5Gcreate2(loc, name.c_str(), H5P_DEFAULT, H5P_DEFAULT, H5P_DEFAULT), "H5Gcreate2", name));
  };
  Handle x = ensure_group(w.get(), "xdmf");
  std::vector<std::string> arrays;
  for (const auto& v : plan.views) {
    arrays.push_back(v.array);
    Handle g = ensure_group(x.get(), v.array);
    detail::write_string_attribute(g.get(), "field", fields[v.field].name);
    detail::write_int_attribute(g.get(), "first_component", static_cast<std::int64_t>(v.first));
    detail::write_int_attribute(g.get(), "components", static_cast<std::int64_t>(v.count));
    const bool copy = sizeof(double) * n * v.count <= detail::max_copied_view_bytes;
    Handle field = open_dataset(w.get(), "/fields/" + fields[v.field].name, h5_path);
    const std::size_t nc = fields[v.field].components;
    for (std::size_t k = 0; k < steps; ++k) {
      if (has_link(g.get(), std::to_string(k))) continue;
      if (copy) {
        const std::vector<double> row = read_rows(field.get(), k, 1, h5_path + ":/fields/" + fields[v.field].name);
        std::vector<double> values(n * v.count);
        for (std::size_t i = 0; i < n; ++i)
          for (std::size_t q = 0; q < v.count; ++q) values[i * v.count + q] = row[i * nc + v.first + q];
        detail::create_view_copy(g.get(), k, n, v.count, values.data(), h5_path + ":/xdmf/" + v.array);
      } else {
        detail::create_view(g.get(), k, "/fields/" + fields[v.field].name, n, nc, v.first, v.count,
                            h5_path + ":/xdmf/" + v.array);
      }
      ++created;
    }
  }
  detail::write_string_attribute(x.get(), "arrays", detail::join(arrays, ','));
  detail::write_string_attribute(
      x.get(), "geometry", plan.geometry >= 0 ? plan.views[static_cast<std::size_t>(plan.geometry)].array : "");
  check(H5Fflush(w.get(), H5F_SCOPE_LOCAL), "H5Fflush", h5_path);
  return created;
}

// Where the loads are at every step, and the arrays' values there: on the geometry, else on
// /mesh/position (m.load_values).
void load_values(hid_t file, const std::string& h5_path, const std::vector<detail::XdmfFieldInfo>& fields,
                 const detail::XdmfPlan& plan, const std::vector<double>& s, std::size_t steps, detail::XdmfModel& m) {
  const std::size_t n = s.size();
  const std::size_t W = m.load_width();
  m.load_values.assign(W * steps * m.loads, 0.0);
  std::vector<double> xyz(3 * n), rows(W * n);
  if (plan.geometry < 0) {
    Handle p = open_dataset(file, "/mesh/position", h5_path);
    xyz = read_rows(p.get(), 0, n, h5_path + ":/mesh/position");
  }
  std::vector<Handle> datasets;  // per field
  for (const auto& fi : fields) datasets.push_back(open_dataset(file, "/fields/" + fi.name, h5_path));
  for (std::size_t k = 0; k < steps; ++k) {
    std::vector<std::vector<double>> step(fields.size());
    auto field_row = [&](std::size_t f) -> const std::vector<double>& {
      if (step[f].empty()) step[f] = read_rows(datasets[f].get(), k, 1, h5_path + ":/fields/" + fields[f].name);
      return step[f];
    };
    for (std::size_t i = 0; i < n; ++i) {
      double* out = &rows[W * i];
      if (plan.geometry >= 0) {
        const detail::XdmfView& g = plan.views[static_cast<std::size_t>(plan.geometry)];
        const auto& r = field_row(g.field);
        std::copy_n(r.begin() + static_cast<std::ptrdiff_t>(i * fields[g.field].components + g.first), 3, out);
      } else {
        std::copy_n(xyz.begin() + static_cast<std::ptrdiff_t>(3 * i), 3, out);
      }
      std::size_t at = 3;
      for (const auto& v : plan.views) {
        const auto& r = field_row(v.field);
        std::copy_n(r.begin() + static_cast<std::ptrdiff_t>(i * fields[v.field].components + v.first), v.count,
                    out + at);
        at += v.count;
      }
    }
    for (std::size_t l = 0; l < m.loads; ++l)
      detail::load_point(n, 0, n, s.data(), rows.data(), W, m.sigma[k * m.loads + l],
                         &m.load_values[W * (k * m.loads + l)]);
  }
}

}  // namespace

SidecarResult write_sidecar(const std::string& h5_path, const std::string& xmf_path) {
  detail::silence_hdf5_errors();
  SidecarResult result;
  result.xmf_path = xmf_path;
  if (result.xmf_path.empty()) result.xmf_path = fs::path(h5_path).replace_extension(".xmf").string();

  Handle file = open_file(h5_path, false);
  const hid_t f = file.get();
  if (detail::has_attribute(f, "kind") && detail::read_string_attribute(f, "kind") == "continuation")
    throw OutputError(h5_path + " is a continuation (statics) file: it has no time series for a sidecar");
  if (!detail::has_attribute(f, "steps_written") || !has_link(f, "mesh/s"))
    throw OutputError(h5_path + " is not a traverse time-series output file (no steps_written or /mesh/s)");
  const auto steps = static_cast<std::size_t>(detail::read_int_attribute(f, "steps_written"));
  result.steps = steps;

  std::size_t n = 0;
  std::vector<double> s;
  {
    Handle s_ds = open_dataset(f, "/mesh/s", h5_path);
    n = static_cast<std::size_t>(detail::dataset_dims(s_ds.get(), "/mesh/s").at(0));
    s = read_rows(s_ds.get(), 0, n, h5_path + ":/mesh/s");
  }
  detail::XdmfModel m;
  m.h5_name = detail::sidecar_h5_name(h5_path);
  m.nodes = n;
  {
    Handle t = open_dataset(f, "/time", h5_path);
    m.times = read_rows(t.get(), 0, steps, h5_path + ":/time");
    Handle sg = open_dataset(f, "/sigma", h5_path);
    const auto dims = detail::dataset_dims(sg.get(), "/sigma");
    m.loads = dims.size() == 2 ? static_cast<std::size_t>(dims[1]) : 1;
    m.sigma = read_rows(sg.get(), 0, steps, h5_path + ":/sigma");
  }
  const std::vector<detail::XdmfFieldInfo> fields = read_fields(f, h5_path);
  const detail::XdmfPlan plan = view_plan(f, fields, h5_path);

  std::size_t missing = 0;
  for (const auto& v : plan.views)
    for (std::size_t k = 0; k < steps; ++k)
      if (!has_link(f, "/xdmf/" + v.array + "/" + std::to_string(k))) ++missing;
  if (missing > 0) {
    file.reset();  // every other handle of the read-only file is closed by now
    result.views_created = add_missing_views(h5_path, fields, plan, n, steps);
    file = open_file(h5_path, false);
  }
  m.arrays = plan.views;
  m.geometry = plan.geometry;

  bool loads_on = m.loads > 0 && steps > 0;
  for (double x : m.sigma) loads_on = loads_on && std::isfinite(x);
  if (loads_on) load_values(file.get(), h5_path, fields, plan, s, steps, m);
  detail::write_xdmf_file(result.xmf_path, m);
  return result;
}

}  // namespace traverse::output
