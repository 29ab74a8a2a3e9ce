#include "traverse/mesh/distributed_mesh.hpp"

#include <algorithm>
#include <stdexcept>

namespace traverse::mesh {

DistributedMesh::DistributedMesh(const Mesh1D& mesh, const Teuchos::RCP<const Teuchos::Comm<int>>& comm,
                                 int unknowns_per_node)
    : mesh_(mesh), block_(unknowns_per_node) {
  if (block_ < 1) throw std::invalid_argument("DistributedMesh: unknowns_per_node must be >= 1");
  const int ranks = comm->getSize(), rank = comm->getRank();
  partition_ = partition_nodes(mesh_, ranks);
  first_ = partition_.first[rank];
  count_ = partition_.count[rank];
  gfirst_ = std::max(0, first_ - 1);
  const int glast = std::min(mesh_.num_nodes() - 1, first_ + count_);  // inclusive
  gcount_ = glast - gfirst_ + 1;

  const Tpetra::global_size_t n_nodes = mesh_.num_nodes();
  std::vector<GO> owned(count_), ghosted(gcount_);
  for (int k = 0; k < count_; ++k) owned[k] = first_ + k;
  for (int k = 0; k < gcount_; ++k) ghosted[k] = gfirst_ + k;
  node_map_ = Teuchos::rcp(new Map(n_nodes, owned.data(), count_, 0, comm));
  ghost_node_map_ = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), ghosted.data(),
                                         gcount_, 0, comm));

  std::vector<GO> owned_dofs(static_cast<size_t>(count_) * block_), ghost_dofs(static_cast<size_t>(gcount_) * block_);
  for (int k = 0; k < count_; ++k)
    for (int c = 0; c < block_; ++c) owned_dofs[static_cast<size_t>(k) * block_ + c] = GO(first_ + k) * block_ + c;
  for (int k = 0; k < gcount_; ++k)
    for (int c = 0; c < block_; ++c) ghost_dofs[static_cast<size_t>(k) * block_ + c] = GO(gfirst_ + k) * block_ + c;
  dof_map_ = Teuchos::rcp(new Map(n_nodes * block_, owned_dofs.data(), owned_dofs.size(), 0, comm));
  ghost_dof_map_ = Teuchos::rcp(new Map(Teuchos::OrdinalTraits<Tpetra::global_size_t>::invalid(), ghost_dofs.data(),
                                        ghost_dofs.size(), 0, comm));
  dof_import_ = Teuchos::rcp(new Import(dof_map_, ghost_dof_map_));

  const size_t max_per_row = static_cast<size_t>(3 * block_);
  auto graph = Teuchos::rcp(new Graph(dof_map_, max_per_row));
  std::vector<GO> cols;
  cols.reserve(max_per_row);
  for (int k = 0; k < count_; ++k) {
    const int j = first_ + k;
    cols.clear();
    for (int nb = std::max(0, j - 1); nb <= std::min(mesh_.num_nodes() - 1, j + 1); ++nb)
      for (int c = 0; c < block_; ++c) cols.push_back(GO(nb) * block_ + c);
    for (int c = 0; c < block_; ++c) {
      const GO row = GO(j) * block_ + c;
      graph->insertGlobalIndices(row, Teuchos::ArrayView<const GO>(cols.data(), cols.size()));
    }
  }
  graph->fillComplete();
  graph_ = graph;
}

}  // namespace traverse::mesh
