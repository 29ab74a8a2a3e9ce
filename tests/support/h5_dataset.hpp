#pragma once
// A dataset of an HDF5 file as doubles, for tests that read what the executable wrote.
#include <hdf5.h>

#include <string>
#include <vector>

namespace traverse::testing {

/// Every value of dataset `name` of `file` (any rank, row-major); `rows`: its first dimension.
inline std::vector<double> h5_dataset(const std::string& file, const std::string& name, hsize_t* rows = nullptr) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  const hid_t d = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
  const hid_t sp = H5Dget_space(d);
  hsize_t dims[8] = {0, 1, 1, 1, 1, 1, 1, 1};
  const int rank = H5Sget_simple_extent_ndims(sp);
  H5Sget_simple_extent_dims(sp, dims, nullptr);
  hsize_t n = 1;
  for (int i = 0; i < rank; ++i) n *= dims[i];
  std::vector<double> v(n);
  if (n) H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, v.data());
  if (rows) *rows = dims[0];
  H5Sclose(sp);
  H5Dclose(d);
  H5Fclose(f);
  return v;
}

}  // namespace traverse::testing
