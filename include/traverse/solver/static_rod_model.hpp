#pragma once
// The static boundary-value problem of the rod (rod/static_kernels.hpp) as a Thyra model
// evaluator over Tpetra with parameters: x = the static unknowns (r, theta, kappa, n) per node
// on the mesh's dof map, p(0) = the five StaticParameter values (locally replicated), f = the
// static residual with row r owned by the owner of node r / 12, W = its exact Jacobian in one
// Tpetra::CrsMatrix on the mesh graph, refilled in place. Each rank holds the reference
// frames Rbar of its nodes and their ghosts only.
//
// Solver-module header: it exposes Thyra and Tpetra types; users call static_continuation.hpp.
#include <Thyra_LinearOpWithSolveFactoryBase.hpp>
#include <Thyra_PreconditionerFactoryBase.hpp>
#include <Thyra_StateFuncModelEvaluatorBase.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Vector.hpp>
#include <optional>
#include <vector>

#include "traverse/mesh/distributed_mesh.hpp"
#include "traverse/rod/static_problem.hpp"
#include "traverse/solver/block_assembly_model.hpp"

namespace traverse::solver {

class StaticRodModel : public BlockAssemblyModel {
 public:

  /// `mesh`: problem.base.num_cells + 1 nodes, 12 unknowns per node.
  StaticRodModel(const rod::StaticProblem& problem, Teuchos::RCP<const mesh::DistributedMesh> mesh);

  /// Problem (parameter values are the nominal p); the state's frames become the references
  /// Rbar and its unknowns (with theta) the nominal x. `nodes` holds all N + 1 nodes.
  void set_problem(const rod::StaticProblem& problem);
  const rod::StaticProblem& problem() const { return problem_; }
  void set_state(const std::vector<rod::StaticNode>& nodes);
  /// The same from this rank's ghosted nodes only (first_ghosted_node() first).
  void set_local_state(const std::vector<rod::StaticNode>& ghosted);
  /// This rank's ghosted nodes (frames Rbar, unknowns of x), first_ghosted_node() first.
  std::vector<rod::StaticNode> ghosted_nodes(const Vector& x) const;
  /// Writes `ghosted` (as ghosted_nodes returns them) back: all their frames become the
  /// references and the owned ones' unknowns go into x. Every rank must change a ghost the
  /// way its owner changes it (the owner's unknowns are imported on the next evaluation).
  void store_ghosted_nodes(const std::vector<rod::StaticNode>& ghosted, Vector& x);
  /// f and/or W (either may be null) of the static form of `m` (whose loads may differ from
  /// the problem's) at x.
  void fill_model(const Vector& x, const rod::StaticModel& m, Vector* f, Matrix* W) const;
  /// The model evaluator's f and W are those of `m` (loads the parameters cannot express: the
  /// static start's scaled gravity, point and end forces) instead of problem().model(p); the
  /// parameters and DfDp then do not apply. clear_fixed_model() goes back to the problem.
  void set_fixed_model(const rod::StaticModel& m);
  void clear_fixed_model() { fixed_.reset(); }

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
  /// dF/dp_ip at x with parameters p (analytic, rod::static_cell_dfdp / static_end_dfdp).
  /// Also what the model evaluator's DfDp (parameter vector 0, by columns) returns.
  void fill_dfdp(const Vector& x, const std::array<double, rod::num_static_parameters>& p, rod::StaticParameter ip,
                 Vector& dfdp) const;

  Teuchos::RCP<Vector> nominal_x() const { return x0_; }

  // Thyra::ModelEvaluator (the rest is BlockAssemblyModel's)
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> get_p_space(int l) const override;
  Teuchos::RCP<const Teuchos::Array<std::string>> get_p_names(int l) const override;
  Thyra::ModelEvaluatorBase::InArgs<double> getNominalValues() const override;
  Thyra::ModelEvaluatorBase::InArgs<double> createInArgs() const override;

 private:
  Thyra::ModelEvaluatorBase::OutArgs<double> createOutArgsImpl() const override;
  void evalModelImpl(const Thyra::ModelEvaluatorBase::InArgs<double>& in,
                     const Thyra::ModelEvaluatorBase::OutArgs<double>& out) const override;

  enum class Kind { residual_jacobian, mass };
  void fill(const Vector& x, const rod::StaticModel& m, Kind kind, Vector* f, Matrix* W) const;

  rod::StaticProblem problem_;
  std::optional<rod::StaticModel> fixed_;  ///< set_fixed_model
  std::vector<Mat3> Rbar_;  ///< of the ghosted nodes, first_ghosted_node() first
  Teuchos::RCP<const Thyra::VectorSpaceBase<double>> p_space_;
  Teuchos::RCP<const Teuchos::Array<std::string>> p_names_;
  Teuchos::RCP<const mesh::Map> full_map_;
  Teuchos::RCP<const mesh::Import> full_import_;
  Teuchos::RCP<Vector> x0_;
  Teuchos::RCP<Thyra::VectorBase<double>> x0_thyra_, p0_thyra_;
};

}  // namespace traverse::solver
