#pragma once
// The rod's Jacobian in block storage: for each node this rank owns, three b x b blocks, its
// rows' couplings to the previous node (L), to itself (D) and to the next node (U), each
// column-major, b the unknowns per node. The time step's model assembles into it directly
// when the linear solver is the block-tridiagonal LU, which factorises these blocks as they
// are: no sparse matrix is filled and none is copied into blocks.
//
// Two buffers: a fill writes into one that no factorisation holds (values() hands a buffer
// out, and holding it keeps it from being overwritten), so a factorisation stays consistent
// with the matrix it was computed from while the next Jacobian is assembled.
//
// A fill does not clear the buffer first: each row's part of a block (a "chunk": b values)
// is assigned by its first contribution and summed into by the others, and end_fill() zeroes
// the chunks this fill did not reach that still hold values of an earlier one. The kernels
// reach the same chunks at every fill, so in practice nothing is cleared at all. The chunks a
// fill reached also tell whether the couplings are halved (half_couplings()): no L chunk in
// the rows past b/2 and no U chunk before, as the rod's cell rows are laid out, which the LU
// and the products then use.
//
// Solver-module header: it exposes Thyra and Tpetra types.
#include <Thyra_LinearOpDefaultBase.hpp>
#include <Tpetra_MultiVector.hpp>

#include <cstdint>
#include <memory>
#include <vector>

#include "traverse/mesh/distributed_mesh.hpp"

namespace traverse::solver {

class BlockTridiagonalOperator : public Thyra::LinearOpDefaultBase<double> {
 public:
  using MV = Tpetra::MultiVector<double>;

  /// The blocks of `mesh`'s owned nodes, b = mesh->unknowns_per_node(); `space` is the Thyra
  /// vector space of the mesh's dof map (the model's x space).
  BlockTridiagonalOperator(Teuchos::RCP<const mesh::DistributedMesh> mesh,
                           Teuchos::RCP<const Thyra::VectorSpaceBase<double>> space);

  int block_size() const { return b_; }
  int num_nodes() const { return n_; }  ///< owned nodes
  const mesh::DistributedMesh& mesh() const { return *mesh_; }

  /// Starts a fill of the values (3 b^2 per owned node: L, D, U) in a buffer no holder of
  /// values() has. Add to a chunk (local row r, block rel = 0, 1, 2) through add_chunk_rows.
  void begin_fill();
  /// Adds src (rows x b, column-major, leading dimension ld) into the chunks of local rows
  /// r .. r + rows - 1 (all of one node) in block rel (0: L, 1: D, 2: U).
  void add_chunk_rows(long r, int rows, int rel, const double* src, long ld);
  /// Ends the fill: chunks not reached are zero.
  void end_fill();
  /// The current values. Holding the pointer keeps a later begin_fill from writing into them.
  std::shared_ptr<const std::vector<double>> values() const { return buf_[cur_]; }
  /// Whether the current values' L blocks are zero past row b/2 and their U blocks before it
  /// (as the last fill reached them; false before any fill).
  bool half_couplings() const { return half_[cur_]; }
  /// y = A x with `blocks` as the values, `half` their half_couplings() (collective: imports
  /// x's neighbouring nodes).
  void apply_values(const std::vector<double>& blocks, bool half, const MV& x, MV& y) const;

  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> range() const override { return space_; }
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> domain() const override { return space_; }

 protected:
  bool opSupportedImpl(Thyra::EOpTransp t) const override { return t == Thyra::NOTRANS; }
  void applyImpl(Thyra::EOpTransp t, const Thyra::MultiVectorBase<double>& X,
                 const Teuchos::Ptr<Thyra::MultiVectorBase<double>>& Y, double alpha,
                 double beta) const override;

 private:
  Teuchos::RCP<const mesh::DistributedMesh> mesh_;
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> space_;
  int b_ = 0, n_ = 0;
  std::shared_ptr<std::vector<double>> buf_[2];
  std::vector<std::uint8_t> dirty_[2];  ///< per chunk: may hold non-zero values
  std::vector<std::uint8_t> written_;   ///< per chunk: reached by the current fill
  bool half_[2] = {false, false};       ///< per buffer: half_couplings()
  std::size_t n_dirty_[2] = {0, 0};     ///< per buffer: chunks marked dirty
  std::size_t n_written_ = 0;           ///< chunks reached by the current fill
  bool new_chunks_ = false;             ///< the current fill reached a chunk not dirty before
  int cur_ = 0;
  mutable Teuchos::RCP<MV> ghosted_, tmp_;  ///< x on the ghosted map; A x (applyImpl)
};

}  // namespace traverse::solver
