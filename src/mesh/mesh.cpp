#include "traverse/mesh/mesh.hpp"

#include <metis.h>

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace traverse::mesh {

Mesh1D::Mesh1D(double length, int nodes) {
  if (nodes < 2) throw std::invalid_argument("Mesh1D: need at least 2 nodes, got " + std::to_string(nodes));
  if (!(length > 0.0)) throw std::invalid_argument("Mesh1D: length must be > 0");
  ds_ = length / (nodes - 1);
  s_.resize(nodes);
  for (int j = 0; j < nodes; ++j) s_[j] = j * ds_;
  s_.back() = length;
}

void Mesh1D::adjacency(std::vector<int>& xadj, std::vector<int>& adjncy) const {
  const int n = num_nodes();
  xadj.assign(n + 1, 0);
  adjncy.clear();
  for (int j = 0; j < n; ++j) {
    if (j > 0) adjncy.push_back(j - 1);
    if (j + 1 < n) adjncy.push_back(j + 1);
    xadj[j + 1] = static_cast<int>(adjncy.size());
  }
}

Partition partition_nodes(const Mesh1D& mesh, int parts) {
  const int n = mesh.num_nodes();
  if (parts < 1 || parts > n)
    throw std::invalid_argument("partition: cannot split " + std::to_string(n) + " nodes over " +
                                std::to_string(parts) + " ranks (need 1 <= ranks <= nodes)");
  Partition p;
  p.parts = parts;
  p.part_of_node.assign(n, 0);
  if (parts > 1) {
    std::vector<int> xadj, adjncy;
    mesh.adjacency(xadj, adjncy);
    idx_t nvtxs = n, ncon = 1, nparts = parts, objval = 0;
    idx_t options[METIS_NOPTIONS];
    METIS_SetDefaultOptions(options);
    options[METIS_OPTION_SEED] = 1;  // deterministic across ranks and runs
    options[METIS_OPTION_CONTIG] = 1;
    std::vector<idx_t> xa(xadj.begin(), xadj.end()), ad(adjncy.begin(), adjncy.end()), part(n);
    const int rc = METIS_PartGraphKway(&nvtxs, &ncon, xa.data(), ad.data(), nullptr, nullptr, nullptr, &nparts,
                                       nullptr, nullptr, options, &objval, part.data());
    if (rc != METIS_OK) throw std::runtime_error("partition: METIS_PartGraphKway failed with code " + std::to_string(rc));
    p.part_of_node.assign(part.begin(), part.end());
  }
  // Each part must be one contiguous range (a chain cut into pieces). Number the parts in
  // the order they appear along the chain so rank r owns the r-th piece. On tiny graphs
  // METIS may leave a part empty: then the balanced contiguous split (optimal for a chain,
  // edge cut parts - 1) is used instead.
  std::vector<int> order;
  for (int j = 0; j < n; ++j)
    if (j == 0 || p.part_of_node[j] != p.part_of_node[j - 1]) order.push_back(p.part_of_node[j]);
  p.from_metis = static_cast<int>(order.size()) == parts;
  if (!p.from_metis) {
    order.resize(parts);
    std::iota(order.begin(), order.end(), 0);
    for (int j = 0; j < n; ++j) p.part_of_node[j] = static_cast<int>((static_cast<long long>(j) * parts) / n);
  }
  std::vector<int> relabel(parts, -1);
  for (int k = 0; k < parts; ++k) relabel[order[k]] = k;
  p.first.assign(parts, 0);
  p.count.assign(parts, 0);
  for (int j = 0; j < n; ++j) {
    const int k = relabel[p.part_of_node[j]];
    p.part_of_node[j] = k;
    if (p.count[k] == 0) p.first[k] = j;
    ++p.count[k];
  }
  return p;
}

}  // namespace traverse::mesh
