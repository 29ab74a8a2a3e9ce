// Solver parameters and the resolution of the linear solver for a rank count (no MPI needed).
#include <gtest/gtest.h>

#include <cstdio>

#include "traverse/solver/linear_solver_choice.hpp"
#include "traverse/solver/solver_parameters.hpp"
#include "traverse/solver/step_failure.hpp"
#include "traverse/solver/teuchos_params.hpp"

namespace traverse::solver {
namespace {

TEST(SolverParameters, DefaultsAndErrors) {
  const traverse::ParamList p = validated_solver_parameters(traverse::ParamList());
  EXPECT_EQ(p.get<std::string>("Linear Solver"), "auto");
  EXPECT_EQ(p.get<int>("Max Subdivision Depth"), 4);
  EXPECT_EQ(p.get<std::string>("Line Search"), "Full Step");

  traverse::ParamList typo;
  typo.set("Linear Solvr", "KLU2");
  try {
    validated_solver_parameters(typo);
    ADD_FAILURE() << "a misspelt key was accepted";
  } catch (const std::invalid_argument& e) {
    std::printf("misspelt key: %.200s...\n", e.what());
    EXPECT_NE(std::string(e.what()).find("Linear Solvr"), std::string::npos);
  }
  traverse::ParamList bad_value;
  bad_value.set("Preconditioner", "Jacobi");
  EXPECT_THROW(validated_solver_parameters(bad_value), std::invalid_argument);
  traverse::ParamList negative;
  negative.set("Max Subdivision Depth", -1);
  try {
    validated_solver_parameters(negative);
    ADD_FAILURE() << "a negative depth was accepted";
  } catch (const std::invalid_argument& e) {
    std::printf("negative depth: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("Max Subdivision Depth"), std::string::npos);
  }
  // Pass-through sublists are not validated here.
  traverse::ParamList nox;
  nox.sublist("NOX").sublist("Anything").set("goes", 1);
  EXPECT_NO_THROW(validated_solver_parameters(nox));
  // An integer is accepted for a real key (YAML's "Residual Tolerance: 1"), not the reverse.
  traverse::ParamList whole;
  whole.set("Residual Tolerance", 1);
  EXPECT_EQ(validated_solver_parameters(whole).get<double>("Residual Tolerance"), 1.0);
  traverse::ParamList fractional;
  fractional.set("Max Newton Iterations", 2.5);
  try {
    validated_solver_parameters(fractional);
    ADD_FAILURE() << "a real number was accepted for an integer key";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'Max Newton Iterations' must be an int, found a double"), std::string::npos)
        << e.what();
  }
  traverse::ParamList not_a_list;
  not_a_list.set("NOX", 1);
  EXPECT_THROW(validated_solver_parameters(not_a_list), std::invalid_argument);
}

TEST(SolverParameters, TeuchosListsCarryTheSameValues) {
  // The Trilinos side gets the same names, types and order (teuchos_params.hpp).
  traverse::ParamList p = validated_solver_parameters(traverse::ParamList());
  p.sublist("NOX").sublist("Line Search").set("Method", "Backtrack");
  p.sublist("NOX").set("Scales", std::vector<double>{1.0, 2.5});
  const Teuchos::ParameterList t = to_teuchos(p);
  EXPECT_EQ(t.get<std::string>("Linear Solver"), "auto");
  EXPECT_EQ(t.get<int>("Max Newton Iterations"), 20);
  EXPECT_EQ(t.get<double>("Residual Tolerance"), 1e-8);
  EXPECT_EQ(t.get<bool>("Verbose"), true);
  EXPECT_EQ(t.sublist("NOX").sublist("Line Search").get<std::string>("Method"), "Backtrack");
  EXPECT_EQ(t.sublist("NOX").get<Teuchos::Array<double>>("Scales")[1], 2.5);
  EXPECT_EQ(from_teuchos(t), p);
}

TEST(LinearSolverChoice, AutoForTheTimeStepIsGmresWithTheBlockTridiagonalLu) {
  for (int ranks : {1, 2}) {
    const LinearSolverChoice c =
        LinearSolverChoice::resolve(traverse::ParamList(), ranks, LinearSolverChoice::Use::time_step);
    std::printf("auto, time step, %d rank(s): %s\n", ranks, c.resolved.c_str());
    EXPECT_FALSE(c.rerouted);
    EXPECT_FALSE(c.direct);
    EXPECT_EQ(c.stratimikos.get<std::string>("Linear Solver Type"), "Belos");
    const auto& ifp = c.stratimikos.sublist("Preconditioner Types").sublist("Ifpack2");
    EXPECT_EQ(ifp.get<std::string>("Prec Type"), "BLOCK_TRIDIAGONAL");
  }
  // An explicit choice is kept for the time step too.
  traverse::ParamList klu;
  klu.set("Linear Solver", "KLU2");
  EXPECT_EQ(LinearSolverChoice::resolve(klu, 1, LinearSolverChoice::Use::time_step).resolved,
            "Amesos2 KLU2 (direct)");
}

TEST(LinearSolverChoice, AutoForStaticsPicksKlu2OnOneRankAndGmresOnMore) {
  const LinearSolverChoice one = LinearSolverChoice::resolve(traverse::ParamList(), 1);
  EXPECT_EQ(one.resolved, "Amesos2 KLU2 (direct)");
  EXPECT_TRUE(one.direct);
  EXPECT_FALSE(one.rerouted);
  EXPECT_EQ(one.stratimikos.get<std::string>("Linear Solver Type"), "Amesos2");
  const LinearSolverChoice two = LinearSolverChoice::resolve(traverse::ParamList(), 2);
  std::printf("auto on 2 ranks: %s\n", two.resolved.c_str());
  EXPECT_FALSE(two.rerouted);
  EXPECT_EQ(two.stratimikos.get<std::string>("Linear Solver Type"), "Belos");
  const auto& ifp = two.stratimikos.sublist("Preconditioner Types").sublist("Ifpack2");
  EXPECT_EQ(ifp.get<std::string>("Prec Type"), "SCHWARZ");
  EXPECT_EQ(ifp.sublist("Ifpack2 Settings").get<std::string>("subdomain solver name"), "AMESOS2");
}

TEST(LinearSolverChoice, Klu2OnSeveralRanksIsReroutedOrRefused) {
  traverse::ParamList p;
  p.set("Linear Solver", "KLU2");
  const LinearSolverChoice c = LinearSolverChoice::resolve(p, 2);
  std::printf("KLU2 on 2 ranks: %s\n", c.resolved.c_str());
  EXPECT_TRUE(c.rerouted);
  EXPECT_FALSE(c.direct);
  EXPECT_EQ(c.requested, "Amesos2 KLU2 (direct)");
  EXPECT_EQ(c.stratimikos.get<std::string>("Linear Solver Type"), "Belos");
  EXPECT_NE(c.resolved.find("rerouted from Amesos2 KLU2"), std::string::npos);

  p.set("On Broken Direct Solver", "refuse");
  EXPECT_THROW(LinearSolverChoice::resolve(p, 3), std::invalid_argument);
  EXPECT_NO_THROW(LinearSolverChoice::resolve(p, 1));

  // The same rule applies to a full Stratimikos pass-through list.
  traverse::ParamList q;
  q.sublist("Stratimikos").set("Linear Solver Type", "Amesos2");
  const LinearSolverChoice s1 = LinearSolverChoice::resolve(q, 1);
  EXPECT_FALSE(s1.rerouted);
  EXPECT_EQ(s1.resolved, "Stratimikos Amesos2 + ML");
  const LinearSolverChoice s2 = LinearSolverChoice::resolve(q, 2);
  EXPECT_TRUE(s2.rerouted);
  std::printf("pass-through Amesos2 on 2 ranks: %s\n", s2.resolved.c_str());
}

TEST(StepFailure, MessageCarriesTimesAndReason) {
  NewtonReport r;
  r.status = "failed: no convergence in 3 Newton iterations";
  r.iterations = 3;
  const StepFailure e(0.25, 0.5, 0.375, 0.125, 2, r);
  std::printf("%s\n", e.what());
  EXPECT_DOUBLE_EQ(e.time(), 0.25);
  EXPECT_DOUBLE_EQ(e.failed_step(), 0.125);
  EXPECT_EQ(e.depth(), 2);
  EXPECT_NE(std::string(e.what()).find("t = 0.25 s with dt = 0.5 s"), std::string::npos);
  EXPECT_NE(std::string(e.what()).find("no convergence in 3 Newton iterations"), std::string::npos);
}

}  // namespace
}  // namespace traverse::solver
