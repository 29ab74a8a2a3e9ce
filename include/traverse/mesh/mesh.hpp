#pragma once
// A 1D mesh: nodes along the arclength of one or more rods. Trilinos-free.
#include <vector>

namespace traverse::mesh {

/// Nodes of one structure (rod or beam) with uniform spacing. The node graph connects
/// consecutive nodes; several structures would be several chains (global node numbers
/// stay unique, so the partition and the maps below handle them unchanged).
class Mesh1D {
 public:
  /// `nodes` >= 2 nodes spanning [0, length] uniformly.
  Mesh1D(double length, int nodes);

  int num_nodes() const { return static_cast<int>(s_.size()); }
  int num_cells() const { return num_nodes() - 1; }
  double length() const { return s_.back(); }
  double ds() const { return ds_; }                  ///< spacing [m]
  double s(int j) const { return s_[j]; }             ///< arclength of node j [m]
  const std::vector<double>& arclength() const { return s_; }

  /// Node graph in CSR form (xadj, adjncy), as METIS wants it.
  void adjacency(std::vector<int>& xadj, std::vector<int>& adjncy) const;

 private:
  std::vector<double> s_;
  double ds_;
};

/// Assignment of nodes to parts (MPI ranks).
struct Partition {
  int parts = 1;
  std::vector<int> part_of_node;  ///< part index of each node
  /// First node and node count of each part; valid because each part of a chain is one
  /// contiguous range of nodes (checked when the partition is built).
  std::vector<int> first, count;
  /// False when METIS left a part empty or split (tiny graphs) and the balanced contiguous
  /// split was used instead.
  bool from_metis = true;
};

/// Partitions the node graph into `parts` parts with METIS (k-way, minimising the edge cut),
/// one contiguous range of nodes per part. Throws std::invalid_argument if parts < 1 or
/// parts > nodes. Deterministic: every rank computing it gets the same answer.
Partition partition_nodes(const Mesh1D& mesh, int parts);

}  // namespace traverse::mesh
