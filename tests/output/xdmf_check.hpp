#pragma once
// Minimal XDMF sidecar check for the tests: the tags nest and close, every HDF DataItem
// names an existing dataset of the declared dimensions, hyperslabs stay inside it, and
// there is one grid per written step. Returns a list of problems (empty: fine).
#include <hdf5.h>

#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

namespace traverse::output::test {

struct XdmfReport {
  std::vector<std::string> problems;
  std::size_t grids = 0;
  std::size_t hdf_items = 0;
  std::size_t hyperslabs = 0;
};

inline std::vector<unsigned long long> parse_dims(const std::string& text) {
  std::istringstream in(text);
  std::vector<unsigned long long> v;
  unsigned long long x = 0;
  while (in >> x) v.push_back(x);
  return v;
}

inline XdmfReport check_xdmf(const std::string& xmf_path, const std::string& h5_path) {
  XdmfReport rep;
  std::ifstream in(xmf_path);
  if (!in) {
    rep.problems.push_back("cannot open " + xmf_path);
    return rep;
  }
  std::stringstream buf;
  buf << in.rdbuf();
  const std::string text = buf.str();

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
    if (name == "Grid" && tag.find("GridType=\"Uniform\"") != std::string::npos) ++rep.grids;
    if (tag.back() != '/') stack.push_back(name);
  }
  if (!stack.empty()) rep.problems.push_back("unclosed <" + stack.back() + ">");
  if (text.find("<Xdmf") == std::string::npos) rep.problems.push_back("no <Xdmf> root");

  // 2. HDF data items, with the hyperslab selection that may precede them.
  // Same access properties as traverse::output::Reader (no file locking), so that the file
  // may be open in a Reader at the same time.
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
  const std::regex slab_re(
      "<DataItem Dimensions=\"3 3\" Format=\"XML\">([0-9 ]+)</DataItem>\\s*"
      "<DataItem Dimensions=\"([0-9 ]+)\"[^>]*Format=\"HDF\">([^<]+)</DataItem>");
  const std::regex item_re("<DataItem Dimensions=\"([0-9 ]+)\"[^>]*Format=\"HDF\">([^<]+)</DataItem>");
  auto check_item = [&](const std::string& dims_text, const std::string& ref,
                        const std::vector<unsigned long long>* slab) {
    ++rep.hdf_items;
    const std::size_t colon = ref.find(':');
    const std::string dset = colon == std::string::npos ? ref : ref.substr(colon + 1);
    hid_t d = H5Dopen2(file, dset.c_str(), H5P_DEFAULT);
    if (d < 0) {
      rep.problems.push_back("missing dataset " + ref);
      return;
    }
    hid_t sp = H5Dget_space(d);
    hsize_t dims[8];
    const int nd = H5Sget_simple_extent_dims(sp, dims, nullptr);
    H5Sclose(sp);
    H5Dclose(d);
    const auto declared = parse_dims(dims_text);
    std::vector<unsigned long long> actual(dims, dims + nd);
    if (declared != actual) rep.problems.push_back("dimensions of " + ref + " differ from the file");
    if (slab != nullptr) {
      ++rep.hyperslabs;
      if (slab->size() != 9 || actual.size() != 3) {
        rep.problems.push_back("bad hyperslab on " + ref);
        return;
      }
      for (std::size_t k = 0; k < 3; ++k)
        if ((*slab)[k] + (*slab)[3 + k] * ((*slab)[6 + k] - 1) >= actual[k])
          rep.problems.push_back("hyperslab outside " + ref);
    }
  };
  for (std::sregex_iterator it(text.begin(), text.end(), slab_re), end; it != end; ++it) {
    const auto slab = parse_dims((*it)[1]);
    check_item((*it)[2], (*it)[3], &slab);
  }
  const std::size_t slab_items = rep.hdf_items;
  std::size_t all_items = 0;
  for (std::sregex_iterator it(text.begin(), text.end(), item_re), end; it != end; ++it) {
    ++all_items;
    const std::string whole = (*it)[0];
    // Items already checked as hyperslab sources are skipped (their ref appears with a slab).
    if (whole.find("/fields/") != std::string::npos) continue;
    check_item((*it)[1], (*it)[2], nullptr);
  }
  if (all_items < slab_items) rep.problems.push_back("inconsistent data item count");
  H5Fclose(file);
  return rep;
}

}  // namespace traverse::output::test
