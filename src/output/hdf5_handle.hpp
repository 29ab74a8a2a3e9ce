#pragma once
// Private helpers of the output module around the HDF5 C API: an owning handle, error
// translation into OutputError, and attribute access. Not installed, not public.
#include <hdf5.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace traverse::output::detail {

/// Owns one HDF5 identifier and closes it with the matching H5*close function.
class Handle {
 public:
  using Closer = herr_t (*)(hid_t);
  Handle() = default;
  Handle(hid_t id, Closer closer) : id_(id), closer_(closer) {}
  ~Handle() { reset(); }
  Handle(const Handle&) = delete;
  Handle& operator=(const Handle&) = delete;
  Handle(Handle&& o) noexcept : id_(o.id_), closer_(o.closer_) { o.id_ = H5I_INVALID_HID; }
  Handle& operator=(Handle&& o) noexcept {
    if (this != &o) {
      reset();
      id_ = o.id_;
      closer_ = o.closer_;
      o.id_ = H5I_INVALID_HID;
    }
    return *this;
  }
  hid_t get() const { return id_; }
  bool valid() const { return id_ >= 0; }
  /// Closes now; returns the close status (0 when there was nothing to close).
  herr_t reset() {
    herr_t rc = 0;
    if (id_ >= 0 && closer_ != nullptr) rc = closer_(id_);
    id_ = H5I_INVALID_HID;
    return rc;
  }
  /// Forgets the identifier without closing it (after the library was shut down).
  void release() { id_ = H5I_INVALID_HID; }

 private:
  hid_t id_ = H5I_INVALID_HID;
  Closer closer_ = nullptr;
};

/// Turns off HDF5's automatic printing of its error stack (errors become exceptions).
void silence_hdf5_errors();

/// Throws OutputError "HDF5 call <call> failed (<what>): <innermost HDF5 messages>" and
/// clears the HDF5 error stack.
[[noreturn]] void throw_hdf5(const char* call, const std::string& what);
inline hid_t check_id(hid_t id, const char* call, const std::string& what) {
  if (id < 0) throw_hdf5(call, what);
  return id;
}
inline void check(herr_t rc, const char* call, const std::string& what) {
  if (rc < 0) throw_hdf5(call, what);
}

Handle file_handle(hid_t id);
Handle group_handle(hid_t id);
Handle dataset_handle(hid_t id);
Handle space_handle(hid_t id);
Handle type_handle(hid_t id);
Handle plist_handle(hid_t id);
Handle attribute_handle(hid_t id);

bool has_attribute(hid_t obj, const std::string& name);
/// Creates or overwrites a scalar variable-length UTF-8 string attribute.
void write_string_attribute(hid_t obj, const std::string& name, const std::string& value);
/// Reads a scalar string attribute, variable or fixed length.
std::string read_string_attribute(hid_t obj, const std::string& name);
void write_int_attribute(hid_t obj, const std::string& name, std::int64_t value);
std::int64_t read_int_attribute(hid_t obj, const std::string& name);
void write_double_attribute(hid_t obj, const std::string& name, double value);
double read_double_attribute(hid_t obj, const std::string& name);
/// Creates or overwrites a 1-D double attribute of values.size() entries.
void write_double_array_attribute(hid_t obj, const std::string& name, const std::vector<double>& values);
/// Reads a double attribute, scalar or 1-D, as its values.
std::vector<double> read_double_array_attribute(hid_t obj, const std::string& name);

/// Current extent of a dataset.
std::vector<hsize_t> dataset_dims(hid_t dataset, const std::string& what);
/// Names of the links of a group, in name order.
std::vector<std::string> link_names(hid_t group, const std::string& what);

/// Creates the virtual dataset `<step>` in `group` (the sidecar's view of one step, see
/// xdmf.hpp): step `step` of the dataset `field_path` (steps x nodes x components, in the same
/// file), components [first, first + count); shape (nodes) if count is 1, else (nodes, count).
void create_view(hid_t group, std::size_t step, const std::string& field_path, hsize_t nodes, hsize_t components,
                 hsize_t first, hsize_t count, const std::string& what);

/// Views of at most this many bytes are stored as copies (create_view_copy): an HDF5 object
/// costs about 15 us to create that way against about 50 us (and as much again when the file
/// is closed) for a virtual dataset; larger ones are virtual (no data stored twice).
inline constexpr std::size_t max_copied_view_bytes = 60000;

/// Creates the dataset `<step>` in `group` holding `values` (nodes x count doubles, node-major),
/// contiguous; shape (nodes) if count is 1, else (nodes, count). With MPI-IO every rank must
/// pass the same values.
void create_view_copy(hid_t group, std::size_t step, hsize_t nodes, hsize_t count, const double* values,
                      const std::string& what);
/// The same for many steps of one array: the dataspace and creation properties made once.
class ViewCopies {
 public:
  ViewCopies(hsize_t nodes, hsize_t count, const std::string& what);
  void create(hid_t group, std::size_t step, const double* values) const;

 private:
  Handle space_, dcpl_;
  std::string what_;
};

/// True for names made of [A-Za-z0-9_.-], not empty and not "." or "..".
bool valid_name(const std::string& name);
std::string join(const std::vector<std::string>& parts, char sep);
std::vector<std::string> split(const std::string& text, char sep);

}  // namespace traverse::output::detail
