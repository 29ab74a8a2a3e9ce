// Solver parameters and the resolution of the linear solver for a rank count (no MPI needed).
#include <gtest/gtest.h>

#include <Teuchos_ParameterList.hpp>

#include <cstdio>
#include <string>
#include <vector>

#include "traverse/solver/linear_solver_choice.hpp"
#include "traverse/solver/solver_parameters.hpp"
#include "traverse/solver/step_failure.hpp"

namespace traverse::solver {
namespace {

TEST(SolverParameters, DefaultsAndErrors) {
  const Teuchos::ParameterList p = validated_solver_parameters(Teuchos::ParameterList());
  EXPECT_EQ(p.get<std::string>("Linear Solver"), "auto");
  EXPECT_EQ(p.get<int>("Max Subdivision Depth"), 4);
  EXPECT_EQ(p.get<std::string>("Line Search"), "Full Step");

  Teuchos::ParameterList typo;
  typo.set("Linear Solvr", "KLU2");
  try {
    validated_solver_parameters(typo);
    ADD_FAILURE() << "a misspelt key was accepted";
  } catch (const std::invalid_argument& e) {
    std::printf("misspelt key: %.200s...\n", e.what());
    EXPECT_NE(std::string(e.what()).find("Linear Solvr"), std::string::npos);
  }
  Teuchos::ParameterList bad_value;
  bad_value.set("Preconditioner", "Jacobi");
  EXPECT_THROW(validated_solver_parameters(bad_value), std::invalid_argument);
  Teuchos::ParameterList negative;
  negative.set("Max Subdivision Depth", -1);
  try {
    validated_solver_parameters(negative);
    ADD_FAILURE() << "a negative depth was accepted";
  } catch (const std::invalid_argument& e) {
    std::printf("negative depth: %s\n", e.what());
    EXPECT_NE(std::string(e.what()).find("Max Subdivision Depth"), std::string::npos);
  }
  // NOX's pass-through sublist is NOX's to read; a scene's Stratimikos one is handed to a builder
  // with traverse's factories, which refuses a name this Trilinos lacks before any run starts:
  // a solver type, an Amesos2 solver (Debian's has KLU2 only; SuperLU's refusal is Teuchos'
  // StringToIntMap message, passed on without Trilinos' source locations).
  Teuchos::ParameterList nox;
  nox.sublist("NOX").sublist("Anything").set("goes", 1);
  EXPECT_NO_THROW(validated_solver_parameters(nox));
  Teuchos::ParameterList block_lu;
  block_lu.sublist("Stratimikos").set("Linear Solver Type", "Block Tridiagonal LU");
  block_lu.sublist("Stratimikos").set("Preconditioner Type", "None");
  EXPECT_NO_THROW(checked_solver_parameters(block_lu));
  for (const char* which : {"type", "amesos2"}) {
    Teuchos::ParameterList strat;
    Teuchos::ParameterList& st = strat.sublist("Stratimikos");
    st.set("Linear Solver Type", std::string(which) == "type" ? "Foo" : "Amesos2");
    st.sublist("Linear Solver Types").sublist("Amesos2").set("Solver Type", "SuperLU");
    st.set("Preconditioner Type", "None");
    EXPECT_NO_THROW(validated_solver_parameters(strat));  // the keys only: the solver's own calls
    try {
      checked_solver_parameters(strat);
      ADD_FAILURE() << "an unknown Stratimikos name was accepted (" << which << ")";
    } catch (const std::invalid_argument& e) {
      std::printf("Stratimikos %s: %s\n", which, e.what());
      const std::string m = e.what();
      EXPECT_NE(m.find("'Stratimikos'"), std::string::npos) << m;
      EXPECT_NE(m.find(std::string(which) == "type" ? "\"Foo\"" : "\"SuperLU\""), std::string::npos) << m;
      EXPECT_EQ(m.find("Throw number"), std::string::npos) << m;
      EXPECT_EQ(m.find(".cpp:"), std::string::npos) << m;
    }
  }
  // An integer is accepted for a real key (YAML's "Residual Tolerance: 1"), not the reverse.
  Teuchos::ParameterList whole;
  whole.set("Residual Tolerance", 1);
  EXPECT_EQ(validated_solver_parameters(whole).get<double>("Residual Tolerance"), 1.0);
  Teuchos::ParameterList fractional;
  fractional.set("Max Newton Iterations", 2.5);
  try {
    validated_solver_parameters(fractional);
    ADD_FAILURE() << "a real number was accepted for an integer key";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'Max Newton Iterations' must be an int, found a double"), std::string::npos)
        << e.what();
  }
  Teuchos::ParameterList not_a_list;
  not_a_list.set("NOX", 1);
  EXPECT_THROW(validated_solver_parameters(not_a_list), std::invalid_argument);
}

TEST(SolverParameters, PassThroughSublistsReachTrilinosUnchanged) {
  // NOX and Stratimikos validate their own sublists: validation must neither add to nor
  // convert what a scene gives there (the names, the types and the order).
  Teuchos::ParameterList given;
  given.set("Residual Tolerance", 1);  // widened to a double
  auto& nox = given.sublist("NOX");
  nox.sublist("Line Search").set("Method", "Backtrack");
  nox.sublist("Line Search").sublist("Backtrack").set("Max Iters", 7);
  nox.set("Scales", Teuchos::Array<double>{1.0, 2.5});
  nox.set("Print", true);
  given.sublist("Stratimikos").set("Linear Solver Type", "Belos");
  const Teuchos::ParameterList p = validated_solver_parameters(given);
  EXPECT_TRUE(p.isType<double>("Residual Tolerance"));
  EXPECT_TRUE(Teuchos::haveSameValues(p.sublist("NOX"), given.sublist("NOX")));
  EXPECT_TRUE(Teuchos::haveSameValues(p.sublist("Stratimikos"), given.sublist("Stratimikos")));
  std::vector<std::string> order;
  for (const auto& e : p.sublist("NOX")) order.push_back(e.first);
  EXPECT_EQ(order, (std::vector<std::string>{"Line Search", "Scales", "Print"}));
  // A sublist given empty stays empty (a missing one is added empty).
  EXPECT_EQ(validated_solver_parameters(Teuchos::ParameterList()).sublist("NOX").numParams(), 0);
}

TEST(LinearSolverChoice, AutoForTheTimeStepIsTheBlockTridiagonalLuThroughStratimikos) {
  for (int ranks : {1, 2}) {
    Teuchos::ParameterList given;
    given.set("Linear Tolerance", 1e-10);
    const LinearSolverChoice c = LinearSolverChoice::resolve(given, ranks, LinearSolverChoice::Use::time_step);
    std::printf("auto, time step, %d rank(s): %s\n", ranks, c.resolved.c_str());
    EXPECT_FALSE(c.rerouted);
    EXPECT_FALSE(c.direct);
    EXPECT_TRUE(c.block_tridiagonal_direct);
    EXPECT_EQ(c.stratimikos.get<std::string>("Linear Solver Type"), kBlockTridiagonalLu);
    EXPECT_EQ(c.stratimikos.sublist("Linear Solver Types").sublist(kBlockTridiagonalLu).get<double>("Tolerance"),
              1e-10);
  }
  // GMRES preconditioned by the block LU on 2 ranks keeps Belos with the Ifpack2 entry.
  Teuchos::ParameterList gmres;
  gmres.set("Linear Solver", "GMRES");
  gmres.set("Preconditioner", "BLOCK_TRIDIAGONAL");
  const LinearSolverChoice g = LinearSolverChoice::resolve(gmres, 2, LinearSolverChoice::Use::time_step);
  EXPECT_FALSE(g.block_tridiagonal_direct);
  EXPECT_EQ(g.stratimikos.get<std::string>("Linear Solver Type"), "Belos");
  EXPECT_EQ(g.stratimikos.sublist("Preconditioner Types").sublist("Ifpack2").get<std::string>("Prec Type"),
            "BLOCK_TRIDIAGONAL");
  // An explicit choice is kept for the time step too.
  Teuchos::ParameterList klu;
  klu.set("Linear Solver", "KLU2");
  EXPECT_EQ(LinearSolverChoice::resolve(klu, 1, LinearSolverChoice::Use::time_step).resolved,
            "Amesos2 KLU2 (direct)");
}

TEST(LinearSolverChoice, AutoForStaticsPicksKlu2OnOneRankAndGmresOnMore) {
  const LinearSolverChoice one = LinearSolverChoice::resolve(Teuchos::ParameterList(), 1);
  EXPECT_EQ(one.resolved, "Amesos2 KLU2 (direct)");
  EXPECT_TRUE(one.direct);
  EXPECT_FALSE(one.rerouted);
  EXPECT_EQ(one.stratimikos.get<std::string>("Linear Solver Type"), "Amesos2");
  const LinearSolverChoice two = LinearSolverChoice::resolve(Teuchos::ParameterList(), 2);
  std::printf("auto on 2 ranks: %s\n", two.resolved.c_str());
  EXPECT_FALSE(two.rerouted);
  EXPECT_EQ(two.stratimikos.get<std::string>("Linear Solver Type"), "Belos");
  const auto& ifp = two.stratimikos.sublist("Preconditioner Types").sublist("Ifpack2");
  EXPECT_EQ(ifp.get<std::string>("Prec Type"), "SCHWARZ");
  EXPECT_EQ(ifp.sublist("Ifpack2 Settings").get<std::string>("subdomain solver name"), "AMESOS2");
}

TEST(LinearSolverChoice, Klu2OnSeveralRanksIsReroutedOrRefused) {
  Teuchos::ParameterList p;
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
  Teuchos::ParameterList q;
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
