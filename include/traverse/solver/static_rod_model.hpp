#pragma once
// The static boundary-value problem of the rod (rod/static_kernels.hpp) as a Thyra model
// evaluator over Tpetra with parameters: x = the static unknowns (r, theta, kappa, n) per node
// on the mesh's dof map, p(0) = the five StaticParameter values (locally replicated), f = the
// static residual with row r owned by the owner of node r / 12, W = its exact Jacobian in one
// Tpetra::CrsMatrix on the mesh graph, refilled in place. The reference frames Rbar of all
// nodes are held on every rank (they change only by rebase_frames between runs).
//
// Solver-module header: it exposes Thyra and Tpetra types; users call static_continuation.hpp.
#include <Thyra_LinearOpWithSolveFactoryBase.hpp>
#include <Thyra_PreconditionerFactoryBase.hpp>
#include <Thyra_StateFuncModelEvaluatorBase.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Vector.hpp>
#include <vector>

#include "traverse/mesh/distributed_mesh.hpp"
#include "traverse/rod/static_problem.hpp"

namespace traverse::solver {

class StaticRodModel : public Thyra::StateFuncModelEvaluatorBase<double> {
 public:
  using Vector = Tpetra::Vector<double>;
  using Matrix = Tpetra::CrsMatrix<double>;

  /// `mesh`: problem.base.num_cells + 1 nodes, 12 unknowns per node.
  StaticRodModel(const rod::StaticProblem& problem, Teuchos::RCP<const mesh::DistributedMesh> mesh);

  /// Problem (parameter values are the nominal p); the state's frames become the references
  /// Rbar and its unknowns (with theta) the nominal x. `nodes` holds all N + 1 nodes.
  void set_problem(const rod::StaticProblem& problem);
  const rod::StaticProblem& problem() const { return problem_; }
  void set_state(const std::vector<rod::StaticNode>& nodes);

  void set_W_factory(const Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>>& f) { W_factory_ = f; }
  void set_prec_factory(const Teuchos::RCP<Thyra::PreconditionerFactoryBase<double>>& f) { prec_factory_ = f; }

  /// All N + 1 nodes (frames Rbar, unknowns x) from a distributed x, on every rank.
  std::vector<rod::StaticNode> gather(const Vector& x) const;
  /// The owned part of `nodes`' unknowns (theta relative to this model's Rbar must be what
  /// the nodes hold: call set_state first, or pass nodes with the same Rbar).
  void scatter(const std::vector<rod::StaticNode>& nodes, Vector& x) const;
  /// Jacobian (into W) and small-vibration inertia M_s (into M) at x with parameters `p`.
  void fill_jacobian(const Vector& x, const std::array<double, rod::num_static_parameters>& p, Matrix& W) const;
  void fill_mass(const Vector& x, Matrix& M) const;
  /// Residual at x with parameters p.
  void fill_residual(const Vector& x, const std::array<double, rod::num_static_parameters>& p, Vector& f) const;

  const mesh::DistributedMesh& mesh() const { return *mesh_; }
  const Teuchos::RCP<const mesh::DistributedMesh>& mesh_rcp() const { return mesh_; }
  const Teuchos::RCP<Matrix>& jacobian_matrix() const { return W_; }
  Teuchos::RCP<Matrix> new_matrix() const;  ///< a fill-completed zero matrix on the graph
  Teuchos::RCP<Vector> nominal_x() const { return x0_; }
  const std::vector<Mat3>& reference_frames() const { return Rbar_; }

  // Thyra::ModelEvaluator
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> get_x_space() const override;
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> get_f_space() const override;
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> get_p_space(int l) const override;
  Teuchos::RCP<const Teuchos::Array<std::string>> get_p_names(int l) const override;
  Thyra::ModelEvaluatorBase::InArgs<double> getNominalValues() const override;
  Thyra::ModelEvaluatorBase::InArgs<double> createInArgs() const override;
  Teuchos::RCP<Thyra::LinearOpBase<double>> create_W_op() const override;
  Teuchos::RCP<Thyra::PreconditionerBase<double>> create_W_prec() const override;
  Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> get_W_factory() const override;

 private:
  Thyra::ModelEvaluatorBase::OutArgs<double> createOutArgsImpl() const override;
  void evalModelImpl(const Thyra::ModelEvaluatorBase::InArgs<double>& in,
                     const Thyra::ModelEvaluatorBase::OutArgs<double>& out) const override;

  enum class Kind { residual_jacobian, mass };
  std::vector<rod::LocalBlock> blocks(const Vector& x, const rod::StaticModel& m, Kind kind) const;
  void fill(const std::vector<rod::LocalBlock>& bl, Vector* f, Matrix* W) const;

  rod::StaticProblem problem_;
  Teuchos::RCP<const mesh::DistributedMesh> mesh_;
  Eigen::Index row_begin_ = 0, row_end_ = 0;
  std::vector<Mat3> Rbar_;
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> x_space_, p_space_;
  Teuchos::RCP<const Teuchos::Array<std::string>> p_names_;
  Teuchos::RCP<const mesh::Map> full_map_;
  Teuchos::RCP<const mesh::Import> full_import_;
  Teuchos::RCP<Matrix> W_;
  Teuchos::RCP<Thyra::LinearOpBase<double>> W_op_;
  Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> W_factory_;
  Teuchos::RCP<Thyra::PreconditionerFactoryBase<double>> prec_factory_;
  Teuchos::RCP<Vector> x0_;
  Teuchos::RCP<Thyra::VectorBase<double>> x0_thyra_, p0_thyra_;
  mutable Teuchos::RCP<Vector> x_ghosted_;
};

}  // namespace traverse::solver
