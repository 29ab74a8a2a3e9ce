#include "hdf5_handle.hpp"

#include <cstring>

#include "traverse/output/output_error.hpp"

namespace traverse::output::detail {

void silence_hdf5_errors() { H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); }

namespace {
struct ErrorWalk {
  std::vector<std::string> messages;
};
herr_t collect_error(unsigned /*n*/, const H5E_error2_t* err, void* data) {
  auto* walk = static_cast<ErrorWalk*>(data);
  if (err != nullptr && err->desc != nullptr && walk->messages.size() < 3) {
    std::string text = err->desc;
    if (err->func_name != nullptr) text += std::string(" [") + err->func_name + "]";
    walk->messages.push_back(text);
  }
  return 0;
}
}  // namespace

void throw_hdf5(const char* call, const std::string& what) {
  ErrorWalk walk;
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_UPWARD, collect_error, &walk);
  H5Eclear2(H5E_DEFAULT);
  std::string msg = std::string("HDF5 call ") + call + " failed (" + what + ")";
  for (std::size_t i = 0; i < walk.messages.size(); ++i)
    msg += (i == 0 ? ": " : "; ") + walk.messages[i];
  throw OutputError(msg);
}

Handle file_handle(hid_t id) { return Handle(id, H5Fclose); }
Handle group_handle(hid_t id) { return Handle(id, H5Gclose); }
Handle dataset_handle(hid_t id) { return Handle(id, H5Dclose); }
Handle space_handle(hid_t id) { return Handle(id, H5Sclose); }
Handle type_handle(hid_t id) { return Handle(id, H5Tclose); }
Handle plist_handle(hid_t id) { return Handle(id, H5Pclose); }
Handle attribute_handle(hid_t id) { return Handle(id, H5Aclose); }

bool has_attribute(hid_t obj, const std::string& name) {
  const htri_t rc = H5Aexists(obj, name.c_str());
  if (rc < 0) throw_hdf5("H5Aexists", "attribute " + name);
  return rc > 0;
}

namespace {
Handle vl_string_type() {
  Handle t = type_handle(check_id(H5Tcopy(H5T_C_S1), "H5Tcopy", "string type"));
  check(H5Tset_size(t.get(), H5T_VARIABLE), "H5Tset_size", "string type");
  check(H5Tset_cset(t.get(), H5T_CSET_UTF8), "H5Tset_cset", "string type");
  return t;
}

// Opens the attribute `name` of `obj` with file type `type`, creating it (scalar) if
// absent and re-creating it if it exists with another type class.
Handle open_or_create_attribute(hid_t obj, const std::string& name, hid_t type) {
  if (has_attribute(obj, name)) {
    Handle a = attribute_handle(check_id(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "H5Aopen",
                                         "attribute " + name));
    Handle t = type_handle(check_id(H5Aget_type(a.get()), "H5Aget_type", "attribute " + name));
    const htri_t same = H5Tequal(t.get(), type);
    if (same > 0) return a;
    a.reset();
    check(H5Adelete(obj, name.c_str()), "H5Adelete", "attribute " + name);
  }
  Handle space = space_handle(check_id(H5Screate(H5S_SCALAR), "H5Screate", "attribute " + name));
  return attribute_handle(check_id(
      H5Acreate2(obj, name.c_str(), type, space.get(), H5P_DEFAULT, H5P_DEFAULT), "H5Acreate2",
      "attribute " + name));
}

Handle open_attribute(hid_t obj, const std::string& name) {
  return attribute_handle(
      check_id(H5Aopen(obj, name.c_str(), H5P_DEFAULT), "H5Aopen", "attribute " + name));
}
}  // namespace

void write_string_attribute(hid_t obj, const std::string& name, const std::string& value) {
  Handle t = vl_string_type();
  Handle a = open_or_create_attribute(obj, name, t.get());
  const char* p = value.c_str();
  check(H5Awrite(a.get(), t.get(), &p), "H5Awrite", "attribute " + name);
}

std::string read_string_attribute(hid_t obj, const std::string& name) {
  Handle a = open_attribute(obj, name);
  Handle ft = type_handle(check_id(H5Aget_type(a.get()), "H5Aget_type", "attribute " + name));
  if (H5Tget_class(ft.get()) != H5T_STRING)
    throw OutputError("attribute " + name + " is not a string");
  const htri_t is_vl = H5Tis_variable_str(ft.get());
  check(is_vl, "H5Tis_variable_str", "attribute " + name);
  if (is_vl > 0) {
    Handle mt = vl_string_type();
    char* p = nullptr;
    check(H5Aread(a.get(), mt.get(), &p), "H5Aread", "attribute " + name);
    std::string out = p != nullptr ? std::string(p) : std::string();
    Handle space = space_handle(check_id(H5Aget_space(a.get()), "H5Aget_space", name));
    H5Dvlen_reclaim(mt.get(), space.get(), H5P_DEFAULT, &p);
    return out;
  }
  const std::size_t size = H5Tget_size(ft.get());
  Handle mt = type_handle(check_id(H5Tcopy(H5T_C_S1), "H5Tcopy", "string type"));
  check(H5Tset_size(mt.get(), size), "H5Tset_size", "string type");
  std::vector<char> buf(size + 1, '\0');
  check(H5Aread(a.get(), mt.get(), buf.data()), "H5Aread", "attribute " + name);
  return std::string(buf.data(), strnlen(buf.data(), size));
}

void write_int_attribute(hid_t obj, const std::string& name, std::int64_t value) {
  Handle a = open_or_create_attribute(obj, name, H5T_STD_I64LE);
  const long long v = value;
  check(H5Awrite(a.get(), H5T_NATIVE_LLONG, &v), "H5Awrite", "attribute " + name);
}

std::int64_t read_int_attribute(hid_t obj, const std::string& name) {
  Handle a = open_attribute(obj, name);
  long long v = 0;
  check(H5Aread(a.get(), H5T_NATIVE_LLONG, &v), "H5Aread", "attribute " + name);
  return v;
}

void write_double_attribute(hid_t obj, const std::string& name, double value) {
  Handle a = open_or_create_attribute(obj, name, H5T_IEEE_F64LE);
  check(H5Awrite(a.get(), H5T_NATIVE_DOUBLE, &value), "H5Awrite", "attribute " + name);
}

double read_double_attribute(hid_t obj, const std::string& name) {
  Handle a = open_attribute(obj, name);
  double v = 0.0;
  check(H5Aread(a.get(), H5T_NATIVE_DOUBLE, &v), "H5Aread", "attribute " + name);
  return v;
}

void write_double_array_attribute(hid_t obj, const std::string& name, const std::vector<double>& values) {
  if (has_attribute(obj, name)) check(H5Adelete(obj, name.c_str()), "H5Adelete", "attribute " + name);
  const hsize_t n = values.size();
  Handle space = space_handle(check_id(H5Screate_simple(1, &n, nullptr), "H5Screate_simple", "attribute " + name));
  Handle a = attribute_handle(check_id(H5Acreate2(obj, name.c_str(), H5T_IEEE_F64LE, space.get(), H5P_DEFAULT,
                                                  H5P_DEFAULT),
                                       "H5Acreate2", "attribute " + name));
  check(H5Awrite(a.get(), H5T_NATIVE_DOUBLE, values.data()), "H5Awrite", "attribute " + name);
}

std::vector<double> read_double_array_attribute(hid_t obj, const std::string& name) {
  Handle a = open_attribute(obj, name);
  Handle space = space_handle(check_id(H5Aget_space(a.get()), "H5Aget_space", "attribute " + name));
  const hssize_t n = H5Sget_simple_extent_npoints(space.get());
  if (n < 0) throw_hdf5("H5Sget_simple_extent_npoints", "attribute " + name);
  std::vector<double> v(static_cast<std::size_t>(n));
  check(H5Aread(a.get(), H5T_NATIVE_DOUBLE, v.data()), "H5Aread", "attribute " + name);
  return v;
}

std::vector<hsize_t> dataset_dims(hid_t dataset, const std::string& what) {
  Handle space = space_handle(check_id(H5Dget_space(dataset), "H5Dget_space", what));
  const int rank = H5Sget_simple_extent_ndims(space.get());
  if (rank < 0) throw_hdf5("H5Sget_simple_extent_ndims", what);
  std::vector<hsize_t> dims(static_cast<std::size_t>(rank));
  if (rank > 0)
    check(H5Sget_simple_extent_dims(space.get(), dims.data(), nullptr),
          "H5Sget_simple_extent_dims", what);
  return dims;
}

namespace {
herr_t collect_link(hid_t /*group*/, const char* name, const H5L_info_t* /*info*/, void* data) {
  static_cast<std::vector<std::string>*>(data)->emplace_back(name);
  return 0;
}
}  // namespace

std::vector<std::string> link_names(hid_t group, const std::string& what) {
  std::vector<std::string> names;
  hsize_t idx = 0;
  check(H5Literate(group, H5_INDEX_NAME, H5_ITER_INC, &idx, collect_link, &names), "H5Literate",
        what);
  return names;
}

void create_view(hid_t group, std::size_t step, const std::string& field_path, hsize_t nodes, hsize_t components,
                 hsize_t first, hsize_t count, const std::string& what) {
  const hsize_t src_dims[3] = {static_cast<hsize_t>(step + 1), nodes, components};
  const hsize_t src_max[3] = {H5S_UNLIMITED, nodes, components};
  Handle src = space_handle(check_id(H5Screate_simple(3, src_dims, src_max), "H5Screate_simple", what));
  const hsize_t start[3] = {static_cast<hsize_t>(step), 0, first}, cnt[3] = {1, nodes, count};
  check(H5Sselect_hyperslab(src.get(), H5S_SELECT_SET, start, nullptr, cnt, nullptr), "H5Sselect_hyperslab", what);
  const hsize_t vdims[2] = {nodes, count};
  Handle vspace = space_handle(check_id(H5Screate_simple(count == 1 ? 1 : 2, vdims, nullptr), "H5Screate_simple", what));
  Handle dcpl = plist_handle(check_id(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate", what));
  check(H5Pset_virtual(dcpl.get(), vspace.get(), ".", field_path.c_str(), src.get()), "H5Pset_virtual", what);
  const std::string name = std::to_string(step);
  dataset_handle(check_id(
      H5Dcreate2(group, name.c_str(), H5T_IEEE_F64LE, vspace.get(), H5P_DEFAULT, dcpl.get(), H5P_DEFAULT),
      "H5Dcreate2", what + "/" + name));
}

ViewCopies::ViewCopies(hsize_t nodes, hsize_t count, const std::string& what) : what_(what) {
  const hsize_t dims[2] = {nodes, count};
  space_ = space_handle(check_id(H5Screate_simple(count == 1 ? 1 : 2, dims, nullptr), "H5Screate_simple", what));
  dcpl_ = plist_handle(check_id(H5Pcreate(H5P_DATASET_CREATE), "H5Pcreate", what));
  // Contiguous, written once: no fill. (The compact layout, data in the object header, costs
  // more here: its data pass through HDF5's metadata cache and accumulator, docs/output.md.)
  check(H5Pset_fill_time(dcpl_.get(), H5D_FILL_TIME_NEVER), "H5Pset_fill_time", what);
}

void ViewCopies::create(hid_t group, std::size_t step, const double* values) const {
  const std::string name = std::to_string(step);
  Handle d = dataset_handle(check_id(
      H5Dcreate2(group, name.c_str(), H5T_IEEE_F64LE, space_.get(), H5P_DEFAULT, dcpl_.get(), H5P_DEFAULT),
      "H5Dcreate2", what_ + "/" + name));
  check(H5Dwrite(d.get(), H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, values), "H5Dwrite", what_ + "/" + name);
}

void create_view_copy(hid_t group, std::size_t step, hsize_t nodes, hsize_t count, const double* values,
                      const std::string& what) {
  ViewCopies(nodes, count, what).create(group, step, values);
}

bool valid_name(const std::string& name) {
  if (name.empty() || name == "." || name == "..") return false;
  for (const char c : name) {
    const bool ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                    c == '_' || c == '.' || c == '-';
    if (!ok) return false;
  }
  return true;
}

std::string join(const std::vector<std::string>& parts, char sep) {
  std::string out;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    if (i > 0) out += sep;
    out += parts[i];
  }
  return out;
}

std::vector<std::string> split(const std::string& text, char sep) {
  std::vector<std::string> out;
  if (text.empty()) return out;
  std::size_t start = 0;
  while (true) {
    const std::size_t pos = text.find(sep, start);
    if (pos == std::string::npos) {
      out.push_back(text.substr(start));
      break;
    }
    out.push_back(text.substr(start, pos - start));
    start = pos + 1;
  }
  return out;
}

}  // namespace traverse::output::detail
