#pragma once
// Structural XDMF sidecar check for the tests: the tags nest and close, the root is XDMF 3,
// every HDF DataItem names an existing dataset of the declared dimensions (there are no
// hyperslabs: Xdmf3 and meshio do not read them), and it counts the structure's grids (one
// per step) and the loads' grids. Returns a list of problems (empty: fine).
#include <hdf5.h>

#include <fstream>
#include <filesystem>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace traverse::output::test {

struct XdmfReport {
  std::vector<std::string> problems;
  std::size_t grids = 0;       ///< Uniform grids step_<k> of the structure
  std::size_t load_grids = 0;  ///< Uniform grids loads_<k>
  std::size_t hdf_items = 0;
  std::size_t views = 0;       ///< HDF items that name a per-step view /xdmf/...
};

inline std::vector<unsigned long long> parse_dims(const std::string& text) {
  std::istringstream in(text);
  std::vector<unsigned long long> v;
  unsigned long long x = 0;
  while (in >> x) v.push_back(x);
  return v;
}

inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  std::stringstream buf;
  buf << in.rdbuf();
  return buf.str();
}

inline XdmfReport check_xdmf(const std::string& xmf_path, const std::string& h5_path) {
  XdmfReport rep;
  std::ifstream probe(xmf_path);
  if (!probe) {
    rep.problems.push_back("cannot open " + xmf_path);
    return rep;
  }
  const std::string text = slurp(xmf_path);

  // 1. Tags nest and close.
  std::vector<std::string> stack;
  for (std::size_t pos = text.find('<'); pos != std::string::npos; pos = text.find('<', pos + 1)) {
    const std::size_t end = text.find('>', pos);
    if (end == std::string::npos) {
      rep.problems.push_back("unterminated tag at offset " + std::to_string(pos));
      break;
    }
    const std::string tag = text.substr(pos + 1, end - pos - 1);
    if (tag.empty() || tag[0] == '?' || tag[0] == '!') continue;
    if (tag[0] == '/') {
      const std::string name = tag.substr(1);
      if (stack.empty() || stack.back() != name) {
        rep.problems.push_back("closing </" + name + "> does not match <" +
                               (stack.empty() ? std::string("nothing") : stack.back()) + ">");
        break;
      }
      stack.pop_back();
      continue;
    }
    const std::string name = tag.substr(0, tag.find_first_of(" \t\n/"));
    if (name == "Grid" && tag.find("GridType=\"Uniform\"") != std::string::npos) {
      if (tag.find("Name=\"step_") != std::string::npos) ++rep.grids;
      if (tag.find("Name=\"loads_") != std::string::npos) ++rep.load_grids;
    }
    if (tag.back() != '/') stack.push_back(name);
  }
  if (!stack.empty()) rep.problems.push_back("unclosed <" + stack.back() + ">");
  if (text.find("<Xdmf Version=\"3.0\">") == std::string::npos) rep.problems.push_back("no <Xdmf Version=\"3.0\"> root");
  if (text.find("HyperSlab") != std::string::npos) rep.problems.push_back("a HyperSlab item (Xdmf3 and meshio skip it)");

  // 2. HDF data items. Same access properties as traverse::output::Reader (no file locking).
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
#if H5_VERSION_GE(1, 10, 7)
  H5Pset_file_locking(fapl, 0, 1);
#endif
  hid_t file = H5Fopen(h5_path.c_str(), H5F_ACC_RDONLY, fapl);
  H5Pclose(fapl);
  if (file < 0) {
    rep.problems.push_back("cannot open " + h5_path);
    return rep;
  }
  const std::regex item_re("<DataItem Dimensions=\"([0-9 ]+)\"[^>]*Format=\"HDF\">([^<]+)</DataItem>");
  for (std::sregex_iterator it(text.begin(), text.end(), item_re), end; it != end; ++it) {
    ++rep.hdf_items;
    const std::string ref = (*it)[2];
    const std::size_t colon = ref.find(':');
    const std::string dset = colon == std::string::npos ? ref : ref.substr(colon + 1);
    // The file by its absolute path: readers that join a relative name to the folder of the
    // .xmf as they were given it (ParaView, for a sidecar named without a folder) find it too.
    const std::string named = colon == std::string::npos ? std::string() : ref.substr(0, colon);
    const std::string wanted = std::filesystem::absolute(h5_path).lexically_normal().string();
    if (named != wanted) rep.problems.push_back("the item " + ref + " does not name " + wanted);
    if (dset.rfind("/xdmf/", 0) == 0) ++rep.views;
    hid_t d = H5Dopen2(file, dset.c_str(), H5P_DEFAULT);
    if (d < 0) {
      rep.problems.push_back("missing dataset " + ref);
      continue;
    }
    hid_t sp = H5Dget_space(d);
    hsize_t dims[8];
    const int nd = H5Sget_simple_extent_dims(sp, dims, nullptr);
    H5Sclose(sp);
    H5Dclose(d);
    const auto declared = parse_dims((*it)[1]);
    std::vector<unsigned long long> actual(dims, dims + nd);
    if (declared != actual) rep.problems.push_back("dimensions of " + ref + " differ from the file");
  }
  H5Fclose(file);
  return rep;
}

/// Reads a whole dataset of doubles (e.g. a view /xdmf/<array>/<step>), serially.
inline std::vector<double> read_doubles(const std::string& h5_path, const std::string& dataset) {
  std::vector<double> out;
  hid_t fapl = H5Pcreate(H5P_FILE_ACCESS);
#if H5_VERSION_GE(1, 10, 7)
  H5Pset_file_locking(fapl, 0, 1);
#endif
  hid_t file = H5Fopen(h5_path.c_str(), H5F_ACC_RDONLY, fapl);
  H5Pclose(fapl);
  if (file < 0) return out;
  hid_t d = H5Dopen2(file, dataset.c_str(), H5P_DEFAULT);
  if (d >= 0) {
    hid_t sp = H5Dget_space(d);
    out.resize(static_cast<std::size_t>(H5Sget_simple_extent_npoints(sp)));
    if (H5Dread(d, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, out.data()) < 0) out.clear();
    H5Sclose(sp);
    H5Dclose(d);
  }
  H5Fclose(file);
  return out;
}

}  // namespace traverse::output::test
