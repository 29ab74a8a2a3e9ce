#pragma once
// The mesh spread over MPI ranks: Tpetra maps for nodes and unknowns, the importer that
// fills ghost nodes, and the fixed Jacobian graph. Built once per run and reused by every
// Newton iteration and time step.
#include <Teuchos_Comm.hpp>
#include <Teuchos_RCP.hpp>
#include <Tpetra_CrsGraph.hpp>
#include <Tpetra_Import.hpp>
#include <Tpetra_Map.hpp>

#include "traverse/mesh/mesh.hpp"

namespace traverse::mesh {

using Map = Tpetra::Map<>;
using GO = Map::global_ordinal_type;
using LO = Map::local_ordinal_type;
using Graph = Tpetra::CrsGraph<>;
using Import = Tpetra::Import<>;

class DistributedMesh {
 public:
  /// Partitions `mesh` over the ranks of `comm` (METIS) and builds maps for
  /// `unknowns_per_node` unknowns per node. Throws std::invalid_argument when there are
  /// more ranks than nodes.
  DistributedMesh(const Mesh1D& mesh, const Teuchos::RCP<const Teuchos::Comm<int>>& comm, int unknowns_per_node);

  const Mesh1D& mesh() const { return mesh_; }
  const Partition& partition() const { return partition_; }
  int unknowns_per_node() const { return block_; }

  int first_owned_node() const { return first_; }   ///< global index of this rank's first node
  int num_owned_nodes() const { return count_; }
  int first_ghosted_node() const { return gfirst_; }  ///< first node of owned + ghosts
  int num_ghosted_nodes() const { return gcount_; }   ///< owned plus one ghost each side (if any)

  const Teuchos::RCP<const Map>& node_map() const { return node_map_; }          ///< owned nodes
  const Teuchos::RCP<const Map>& ghosted_node_map() const { return ghost_node_map_; }
  const Teuchos::RCP<const Map>& dof_map() const { return dof_map_; }            ///< owned unknowns
  const Teuchos::RCP<const Map>& ghosted_dof_map() const { return ghost_dof_map_; }
  const Teuchos::RCP<const Import>& dof_importer() const { return dof_import_; }  ///< owned -> ghosted
  /// Jacobian graph: the rows of node j couple every unknown of nodes j-1, j, j+1.
  const Teuchos::RCP<const Graph>& graph() const { return graph_; }

 private:
  Mesh1D mesh_;
  Partition partition_;
  int block_;
  int first_ = 0, count_ = 0, gfirst_ = 0, gcount_ = 0;
  Teuchos::RCP<const Map> node_map_, ghost_node_map_, dof_map_, ghost_dof_map_;
  Teuchos::RCP<const Import> dof_import_;
  Teuchos::RCP<const Graph> graph_;
};

}  // namespace traverse::mesh
