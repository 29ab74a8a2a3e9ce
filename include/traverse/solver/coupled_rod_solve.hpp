#pragma once
// The coupled mass's rod step (rod::CoupledRodStepper, docs/rod.md "Coupled mass") solved by
// a RodStepper on any ranks; the planar or the 3D path, any linear solver. No Trilinos solver
// headers.
#include <mpi.h>

#include <memory>

#include "traverse/rod/coupled_mass_rod.hpp"
#include "traverse/solver/rod_stepper.hpp"

namespace traverse::solver {

/// The whole old state (the same on every rank) goes in, each rank keeps its nodes; the
/// solution is gathered; the fields at sigma are summed over the ranks holding the two nodes
/// of sigma's cell (the same weights and sums as rod::point_kinematics, so a run on 1 rank and
/// one on 2 differ only by what their Newton solves differ by). `comm` is the stepper's.
/// Every call is collective.
class DistributedCoupledRodSolve final : public rod::CoupledRodSolve {
 public:
  DistributedCoupledRodSolve(std::unique_ptr<RodStepper> stepper, MPI_Comm comm);
  /// again: RodStepper::redo_step (Newton from the last solution); otherwise the old
  /// state is set and RodStepper::try_step solves from it. Throws PlanarityLost as the
  /// stepper does.
  bool solve(const rod::RodState& old, double dt, bool again, int& newton_iterations) override;
  rod::RodPointKinematics point(double sigma) const override;
  rod::RodState solution() const override;
  RodStepper& stepper() { return *stepper_; }

 private:
  std::unique_ptr<RodStepper> stepper_;
  MPI_Comm comm_;
};

}  // namespace traverse::solver
