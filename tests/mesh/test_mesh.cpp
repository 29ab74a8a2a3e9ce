// Mesh, METIS partition and Tpetra maps/graph, run on 1 and 2 ranks.
#include <gtest/gtest.h>
#include <mpi.h>

#include <Teuchos_DefaultMpiComm.hpp>
#include <Tpetra_Core.hpp>
#include <Tpetra_Vector.hpp>

#include "traverse/mesh/distributed_mesh.hpp"

using namespace traverse::mesh;

TEST(Mesh, UniformNodesAndAdjacency) {
  const Mesh1D m(2.0, 5);
  EXPECT_EQ(m.num_cells(), 4);
  EXPECT_DOUBLE_EQ(m.ds(), 0.5);
  EXPECT_DOUBLE_EQ(m.s(4), 2.0);
  std::vector<int> xadj, adj;
  m.adjacency(xadj, adj);
  EXPECT_EQ(xadj, (std::vector<int>{0, 1, 3, 5, 7, 8}));
  EXPECT_EQ(adj, (std::vector<int>{1, 0, 2, 1, 3, 2, 4, 3}));
  EXPECT_THROW(Mesh1D(1.0, 1), std::invalid_argument);
}

TEST(Mesh, PartitionsAreContiguousAndBalanced) {
  for (int nodes : {2, 3, 10, 101, 1000}) {
    for (int parts = 1; parts <= std::min(nodes, 7); ++parts) {
      const Partition p = partition_nodes(Mesh1D(1.0, nodes), parts);
      int next = 0, smallest = nodes, largest = 0;
      for (int k = 0; k < parts; ++k) {
        EXPECT_EQ(p.first[k], next) << nodes << " nodes, " << parts << " parts";
        for (int j = p.first[k]; j < p.first[k] + p.count[k]; ++j) EXPECT_EQ(p.part_of_node[j], k);
        next += p.count[k];
        smallest = std::min(smallest, p.count[k]);
        largest = std::max(largest, p.count[k]);
      }
      EXPECT_EQ(next, nodes);
      if (nodes >= 100) {
        EXPECT_TRUE(p.from_metis) << nodes << " nodes, " << parts << " parts";
      }
      EXPECT_GE(smallest, 1);
      // METIS allows a small imbalance (3 % by default); allow one node more on small meshes.
      EXPECT_LE(largest, static_cast<int>(std::ceil(1.03 * nodes / parts)) + 1) << nodes << " nodes, " << parts << " parts";
    }
  }
  EXPECT_THROW(partition_nodes(Mesh1D(1.0, 3), 4), std::invalid_argument);
}

TEST(Mesh, DistributedMapsGhostsAndGraph) {
  auto comm = Teuchos::rcp(new Teuchos::MpiComm<int>(MPI_COMM_WORLD));
  const int ranks = comm->getSize(), rank = comm->getRank();
  for (int nodes : {std::max(2, ranks), 11, 200}) {
    const int block = 12;
    DistributedMesh dm(Mesh1D(1.0, nodes), comm, block);
    // Ownership covers every node exactly once.
    int owned = dm.num_owned_nodes(), total = 0;
    MPI_Allreduce(&owned, &total, 1, MPI_INT, MPI_SUM, MPI_COMM_WORLD);
    EXPECT_EQ(total, nodes);
    EXPECT_EQ(dm.dof_map()->getGlobalNumElements(), static_cast<size_t>(nodes * block));
    EXPECT_EQ(dm.dof_map()->getNodeNumElements(), static_cast<size_t>(owned * block));
    // Ghosts: one node on each side that has a neighbour on another rank.
    const int expected_ghosts = (dm.first_owned_node() > 0) + (dm.first_owned_node() + owned < nodes);
    EXPECT_EQ(dm.num_ghosted_nodes(), owned + expected_ghosts);
    if (ranks == 1) {
      EXPECT_EQ(expected_ghosts, 0);
    }
    // Import fills ghost values from their owners.
    Tpetra::Vector<> x(dm.dof_map()), xg(dm.ghosted_dof_map());
    auto xv = x.getLocalViewHost(Tpetra::Access::OverwriteAll);
    for (size_t i = 0; i < x.getLocalLength(); ++i) xv(i, 0) = static_cast<double>(dm.dof_map()->getGlobalElement(i));
    xg.doImport(x, *dm.dof_importer(), Tpetra::INSERT);
    auto gv = xg.getLocalViewHost(Tpetra::Access::ReadOnly);
    for (size_t i = 0; i < xg.getLocalLength(); ++i)
      EXPECT_EQ(gv(i, 0), static_cast<double>(dm.ghosted_dof_map()->getGlobalElement(i)));
    // Graph: rows of node j couple all unknowns of nodes j-1..j+1.
    const auto& g = *dm.graph();
    for (int k = 0; k < owned; ++k) {
      const int j = dm.first_owned_node() + k;
      const size_t neighbours = (j > 0) + 1 + (j + 1 < nodes);
      EXPECT_EQ(g.getNumEntriesInGlobalRow(GO(j) * block), neighbours * block);
    }
    if (rank == 0) std::cout << "  " << nodes << " nodes on " << ranks << " ranks: rank 0 owns " << owned << "\n";
  }
}

int main(int argc, char** argv) {
  Tpetra::ScopeGuard scope(&argc, &argv);
  ::testing::InitGoogleTest(&argc, argv);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank != 0) ::testing::GTEST_FLAG(output) = "";
  return RUN_ALL_TESTS();
}
