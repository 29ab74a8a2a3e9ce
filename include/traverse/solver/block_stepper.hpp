#pragma once
// The rod's time stepper in one process without Tpetra (a RodStepper): the step's blocks
// (rod::StepAssembly over the whole rod) go into block storage and BlockNewton solves them
// with the block-tridiagonal LU. The same steps as DistributedStepper on one rank with the
// same parameters (it then runs the same BlockNewton on the same assembly): the states agree
// bit for bit. Eigen, the parameter list (core/param_list.hpp) and the rod kernels only: a run that steps with
// it needs neither Kokkos nor MPI started (docs/developer.md, "Start-up").
#include "traverse/core/param_list.hpp"

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "traverse/solver/rod_stepper.hpp"

namespace traverse::solver {

/// Whether BlockStepper can step a run with these solver parameters (validated or not) in one
/// process: the block-tridiagonal LU as the time step's direct solver and BlockNewton
/// (block_newton_applies). Throws std::invalid_argument for parameters the steppers refuse.
bool block_stepper_applies(const ParamList& params);

class BlockStepper : public RodStepper {
 public:
  /// Throws std::invalid_argument when the parameters are bad or do not allow it
  /// (block_stepper_applies). The state starts as the straight rest state at t = 0.
  BlockStepper(rod::RodModel model, const ParamList& params = ParamList());
  ~BlockStepper() override;

  rod::RodState gather_state() const override;  ///< the whole state (it holds every node)
  std::string newton_implementation() const override { return "block storage"; }
  ReuseCounters reuse_counters() const override;

 protected:
  void rebuild() override;
  void set_old_level(std::vector<rod::RodNode> ghosted_old_nodes, const rod::StepTimes& step) override;
  const std::vector<rod::RodNode>& old_level() const override;
  NewtonReport solve_level(std::vector<VecX>& xg, std::optional<rod::InitialGuess> guess, StepReport& sr) override;
  double dropped_residual_everywhere() const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace traverse::solver
