#include "linear_solver_builder.hpp"

#include <Stratimikos_DefaultLinearSolverBuilder.hpp>
#include <Teuchos_AbstractFactoryStd.hpp>

#include "reusable_ifpack2_factory.hpp"

namespace traverse::solver {

LinearSolverObjects build_linear_solver(const LinearSolverChoice& choice) {
  Stratimikos::DefaultLinearSolverBuilder builder;
  builder.setPreconditioningStrategyFactory(
      Teuchos::abstractFactoryStd<Thyra::PreconditionerFactoryBase<double>, ReusableIfpack2Factory>(),
      "Ifpack2");
  builder.setParameterList(Teuchos::rcp(new Teuchos::ParameterList(choice.stratimikos)));
  Teuchos::RCP<Thyra::LinearOpWithSolveFactoryBase<double>> lows = builder.createLinearSolveStrategy("");
  LinearSolverObjects out;
  if (lows->acceptsPreconditionerFactory()) {
    out.prec = lows->getPreconditionerFactory();
    if (!out.prec.is_null()) lows->unsetPreconditionerFactory(nullptr, nullptr);
  }
  out.lows = lows;
  return out;
}

}  // namespace traverse::solver
