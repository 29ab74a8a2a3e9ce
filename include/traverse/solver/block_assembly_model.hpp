#pragma once
// The plumbing shared by the rod's Thyra model evaluators (the time step, RodStepModel, and
// the static problem, StaticRodModel), written once: x and f on the mesh's dof map, one W
// Tpetra::CrsMatrix on the mesh's fixed graph (created once, refilled in place), the linear
// solver and preconditioner factories, the ghosted import of x, and the scatter of the
// kernels' blocks (rod::LocalBlock: rows, node columns, residual, Jacobian blocks) into f
// and W. A derived model supplies only its kernel blocks and its InArgs (parameters).
//
// Solver-module header: it exposes Thyra and Tpetra types.
#include <Thyra_LinearOpWithSolveFactoryBase.hpp>
#include <Thyra_PreconditionerFactoryBase.hpp>
#include <Thyra_StateFuncModelEvaluatorBase.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Vector.hpp>
#include <string>
#include <vector>

#include "traverse/mesh/distributed_mesh.hpp"
#include "traverse/rod/rod_kernels.hpp"

namespace traverse::solver {

class BlockTridiagonalOperator;

class BlockAssemblyModel : public Thyra::StateFuncModelEvaluatorBase<double> {
 public:
  using Vector = Tpetra::Vector<double>;
  using Matrix = Tpetra::CrsMatrix<double>;

  /// Linear solver and (optional) preconditioner factories, e.g. from Stratimikos.
  void set_W_factory(const Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>>& f) { W_factory_ = f; }
  void set_prec_factory(const Teuchos::RCP<Thyra::PreconditionerFactoryBase<double>>& f) { prec_factory_ = f; }
  const Teuchos::RCP<Thyra::PreconditionerFactoryBase<double>>& prec_factory() const { return prec_factory_; }

  /// W as a CrsMatrix on the mesh graph (null with block storage).
  const Teuchos::RCP<Matrix>& jacobian_matrix() const { return W_; }
  bool block_storage() const { return !W_blocks_.is_null(); }
  const mesh::DistributedMesh& mesh() const { return *mesh_; }
  const Teuchos::RCP<const mesh::DistributedMesh>& mesh_rcp() const { return mesh_; }
  /// A fill-completed zero matrix on the mesh graph (same structure as W).
  Teuchos::RCP<Matrix> new_matrix() const;

  // Thyra::ModelEvaluator (common part)
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> get_x_space() const override { return x_space_; }
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> get_f_space() const override { return x_space_; }
  /// The same Thyra wrapper of the same W matrix on every call (W is reused, never reallocated).
  Teuchos::RCP<Thyra::LinearOpBase<double>> create_W_op() const override { return W_op_; }
  /// A preconditioner of the prec factory (null without one).
  Teuchos::RCP<Thyra::PreconditionerBase<double>> create_W_prec() const override;
  Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> get_W_factory() const override {
    return W_factory_;
  }

 protected:
  /// `mesh` with `unknowns_per_node` unknowns per node; `name` is used in messages and the
  /// model descriptions. Creates W: a CrsMatrix on mesh->graph(), or with `block_storage` a
  /// BlockTridiagonalOperator (for the block-tridiagonal LU, which factorises the blocks as
  /// they are).
  BlockAssemblyModel(Teuchos::RCP<const mesh::DistributedMesh> mesh, int unknowns_per_node, std::string name,
                     bool block_storage = false);

  /// Adds kernel blocks into f and W (either may be null): the constructor zeroes them, add()
  /// sums a block's owned rows, finish() completes W. For this model's own W the values are
  /// added in place at precomputed positions (no fillComplete; same sums, same order as
  /// sumIntoGlobalValues, which is used for any other matrix on the graph), or into its blocks
  /// (block storage).
  class Scatter {
   public:
    Scatter(const BlockAssemblyModel& model, Vector* f, Matrix* W);
    /// Into f and this model's own W, whichever storage it has (own_W false: f alone).
    Scatter(const BlockAssemblyModel& model, Vector* f, bool own_W);
    void add(const rod::LocalBlock& b);
    void finish();

   private:
    void add_to_blocks(const rod::LocalBlock& b);
    const BlockAssemblyModel& m_;
    Vector* f_;
    Matrix* W_;
    bool direct_;
    BlockTridiagonalOperator* blocks_ = nullptr;  ///< block storage being filled (else null)
    Teuchos::ArrayRCP<double> fd_;
    Matrix::local_matrix_host_type lcl_;
    std::vector<mesh::GO> cols_;
    std::vector<double> vals_;
  };

  /// What an evaluation asks for: x, f (null if not asked), this model's own W, another W
  /// (null if not asked; checked to be a CrsMatrix on the mesh graph), and whether a
  /// preconditioner is wanted.
  struct Request {
    Teuchos::RCP<const Vector> x;
    Teuchos::RCP<Vector> f;
    bool W_own = false;
    Matrix* W_other = nullptr;
    bool want_prec = false;
  };
  Request request(const Thyra::ModelEvaluatorBase::InArgs<double>& in,
                  const Thyra::ModelEvaluatorBase::OutArgs<double>& out) const;
  /// Builds the requested preconditioner from this model's W.
  void initialize_prec(const Thyra::ModelEvaluatorBase::OutArgs<double>& out) const;
  /// OutArgs supporting f, W_op and (with a prec factory) W_prec, with `np` parameter vectors.
  Thyra::ModelEvaluatorBase::OutArgsSetup<double> out_args_setup(int np) const;
  /// x imported onto the ghosted dof map (a buffer reused between calls).
  const Vector& ghosted(const Vector& x) const;

  Teuchos::RCP<const mesh::DistributedMesh> mesh_;
  int p_ = 12;                                ///< unknowns per node of x, f and W
  Eigen::Index row_begin_ = 0, row_end_ = 0;  ///< owned global rows [begin, end)
  std::string name_;
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> x_space_;
  Teuchos::RCP<Matrix> W_;                            ///< W as a CrsMatrix (null with block storage)
  Teuchos::RCP<BlockTridiagonalOperator> W_blocks_;  ///< W in block storage (null without)
  Teuchos::RCP<Thyra::LinearOpBase<double>> W_op_;

 private:
  /// Position, within each row of an owned node, of the first entry of node block
  /// (node - 1 + rel), rel = 0, 1, 2 (-1 when absent), the same for all the node's rows; empty
  /// when W's rows do not hold each node's columns contiguously in that way.
  void build_offsets();

  Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> W_factory_;
  Teuchos::RCP<Thyra::PreconditionerFactoryBase<double>> prec_factory_;
  mutable Teuchos::RCP<Vector> x_ghosted_;
  std::vector<int> offsets_;  ///< 3 per owned node (build_offsets)
};

}  // namespace traverse::solver
