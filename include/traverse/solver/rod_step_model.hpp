#pragma once
// One time step of the rod as a Thyra model evaluator over Tpetra: x = new-level unknowns on
// the mesh's dof map (node-major, RodModel layout), f = the step residual with row r owned by
// the owner of node r / p, W = its exact Jacobian in one Tpetra::CrsMatrix on the mesh's fixed
// graph, refilled in place at every evaluation.
//
// Planar fast path: with a rod::PlanarReduction the unknowns and rows are those of the planar
// layout (q = 6 or 12 per node, see rod/planar.hpp); the kernels still see full node blocks
// (the in-plane unknowns embedded, zeros elsewhere) and their blocks are restricted to the
// in-plane rows and columns.
//
// Solver-module header: it exposes Thyra and Tpetra types; the app uses DistributedStepper.
#include <Thyra_LinearOpWithSolveFactoryBase.hpp>
#include <Thyra_PreconditionerFactoryBase.hpp>
#include <Thyra_StateFuncModelEvaluatorBase.hpp>
#include <Tpetra_CrsMatrix.hpp>
#include <Tpetra_Vector.hpp>
#include <functional>
#include <memory>
#include <vector>

#include "traverse/mesh/distributed_mesh.hpp"
#include "traverse/solver/block_assembly_model.hpp"
#include "traverse/rod/planar.hpp"
#include "traverse/rod/rod_kernels.hpp"
#include "traverse/rod/step_assembly.hpp"

namespace traverse::solver {

/// Work counters of the reusing KLU2 factory (make_reusing_klu2_factory).
struct DirectSolverStats {
  int symbolic = 0;      ///< symbolic + numeric factorisations (new matrix object)
  int numeric = 0;       ///< numeric factorisations
  int reused = 0;        ///< initializations that kept the factors (W unchanged)
  double seconds = 0.0;  ///< wall time in the factory's initializeOp [s]
};

/// Amesos2 KLU2 (1 rank) as a Thyra LOWS factory that keeps its Amesos2 solver: symbolic
/// factorisation once per matrix object, then only numeric refactorisations, skipped when
/// `jacobian_version()` (RodStepModel::jacobian_version) is the one last factored. Defined in
/// linear_solver_builder.cpp.
Teuchos::RCP<const Thyra::LinearOpWithSolveFactoryBase<double>> make_reusing_klu2_factory(
    std::function<long()> jacobian_version, std::shared_ptr<DirectSolverStats> stats);

class RodStepModel : public BlockAssemblyModel {
 public:

  /// `mesh` must have model->unknowns_per_node() unknowns per node (planar->unknowns_per_node()
  /// with a planar reduction) and model->num_cells + 1 nodes. Creates the single W: a
  /// CrsMatrix on mesh->graph(), or in block storage (`block_storage`, for the block LU).
  RodStepModel(std::shared_ptr<const rod::RodModel> model,
               Teuchos::RCP<const mesh::DistributedMesh> mesh,
               std::shared_ptr<const rod::PlanarReduction> planar = nullptr, bool block_storage = false);

  /// Old-level states of this rank's ghosted nodes (mesh->first_ghosted_node() ...) and the
  /// step. The nominal x (getNominalValues) is then the old level's unknowns.
  void set_old_level(std::vector<rod::RodNode> ghosted_old_nodes, const rod::StepTimes& step);
  const std::vector<rod::RodNode>& old_ghosted_nodes() const { return asm_.old_nodes(); }
  const rod::StepTimes& step_times() const { return asm_.step(); }
  /// The step's blocks.
  const rod::StepAssembly& assembly() const { return asm_; }

  /// The Newton initial guess `g` of the owned nodes (rod::StepAssembly::initial_guess), on the
  /// dof map.
  void initial_guess(Vector& x, rod::InitialGuess g) const;
  /// Import owned x to the ghosted map and return per ghosted node its full unknown block
  /// (model->unknowns_per_node() entries; on the planar path the in-plane ones embedded).
  std::vector<VecX> ghosted_unknowns(const Vector& x) const;
  /// The planar reduction in use, or null (3D path).
  const rod::PlanarReduction* planar() const { return asm_.planar(); }
  /// Unknowns per node of x, f and W (12 or 24; 6 or 12 on the planar path).
  int unknowns_per_node() const { return p_; }
  /// Planar path: the largest |residual| of the out-of-plane rows (dropped) at the last
  /// residual evaluation on this rank; 0 on the 3D path.
  double last_dropped_residual() const { return dropped_; }

  const rod::RodModel& rod_model() const { return asm_.model(); }
  /// Modified Newton ("Jacobian Reuse"): a W request keeps the W (and preconditioner)
  /// already filled - possibly at an earlier iterate or time step - unless the last max|f|
  /// contraction in this solve was worse than `contraction`, or full Newton is forced.
  void set_jacobian_reuse(bool on, double contraction) {
    reuse_ = on;
    contraction_ = contraction;
  }
  bool jacobian_reuse() const { return reuse_; }
  /// Forces a fresh W at every request (the fallback when a reused W did not converge).
  void set_full_newton(bool on) { full_newton_ = on; }
  /// Whether the current solve (since set_old_level) used a W not filled at its own iterate.
  bool stale_jacobian_used() const { return stale_used_; }
  /// Incremented whenever W's values change (the direct solver refactors only then).
  long jacobian_version() const { return W_version_; }
  /// W requests answered by keeping the previous W (modified Newton).
  int jacobian_reuses() const { return n_reused_; }
  int residual_evaluations() const { return n_f_; }
  int jacobian_evaluations() const { return n_W_; }
  /// Wall time [s] spent in fill() (kernels + assembly) and in preconditioner set-up.
  double assembly_seconds() const { return t_fill_; }
  double preconditioner_seconds() const { return t_prec_; }

  // Thyra::ModelEvaluator (the rest is BlockAssemblyModel's). Evaluating W_prec builds the
  // preconditioner from W at the given x (reusing W when it was just evaluated at that x).
  Thyra::ModelEvaluatorBase::InArgs<double> getNominalValues() const override;
  Thyra::ModelEvaluatorBase::InArgs<double> createInArgs() const override;

 private:
  Thyra::ModelEvaluatorBase::OutArgs<double> createOutArgsImpl() const override;
  void evalModelImpl(const Thyra::ModelEvaluatorBase::InArgs<double>& in,
                     const Thyra::ModelEvaluatorBase::OutArgs<double>& out) const override;

  void ghosted_unknowns_into(const Vector& x, std::vector<VecX>& out) const;
  /// Evaluates at x into f (if not null) and this model's W (own_W) or another matrix on the
  /// graph (other_W, if not null).
  void fill(const Vector& x, Vector* f, bool own_W, Matrix* other_W) const;
  bool same_x(const Vector& x) const;  ///< x == the x at which W was last filled

  rod::StepAssembly asm_;
  mutable double dropped_ = 0.0;
  Teuchos::RCP<Vector> x0_;
  Teuchos::RCP<Thyra::VectorBase<double>> x0_thyra_;
  mutable Teuchos::RCP<Vector> W_at_x_;  ///< x at which W was last filled
  mutable bool W_valid_ = false;
  mutable int n_f_ = 0, n_W_ = 0;
  mutable double t_fill_ = 0.0, t_prec_ = 0.0;
  bool reuse_ = false, full_newton_ = false;
  double contraction_ = 0.25;
  mutable bool W_filled_ = false, stale_used_ = false;
  mutable std::vector<double> f_norms_;  ///< max|f| of this solve's residual evaluations
  mutable long W_version_ = 0;
  /// Newton iterations of the last solve (its W requests; -1 before one), and the W requests
  /// and residual-only evaluations of the current one: the iterate numbered
  /// expected_iterations_ gets its residual alone.
  mutable int expected_iterations_ = -1, W_requests_ = 0, f_evaluations_ = 0;
  mutable int n_reused_ = 0;
};

}  // namespace traverse::solver
