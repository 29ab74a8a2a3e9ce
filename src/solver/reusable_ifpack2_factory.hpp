#pragma once
// A Thyra preconditioner factory for Ifpack2 that reuses the preconditioner object across
// Newton iterations and time steps: the Ifpack2 preconditioner is created and initialize()d
// (symbolic setup) once for the fixed W matrix, then only compute()d (numeric factorisation)
// for each new set of values. Additive Schwarz with overlap on 2+ ranks copies the overlap
// rows at initialize(), so it is re-initialized each time (the object is still reused).
// Registered with Stratimikos as "Ifpack2". Its "Ifpack2 Settings" sublist goes to Ifpack2
// unvalidated by Stratimikos (Ifpack2 validates it), so "subdomain solver name" is accepted.
#include <Thyra_PreconditionerFactoryBase.hpp>
#include <string>

namespace traverse::solver {

struct PreconditionerCounters {
  int created = 0;      ///< Ifpack2 objects created
  int initialized = 0;  ///< initialize() calls (symbolic)
  int computed = 0;     ///< compute() calls (numeric)
};

class ReusableIfpack2Factory : public Thyra::PreconditionerFactoryBase<double> {
 public:
  ReusableIfpack2Factory();

  bool isCompatible(const Thyra::LinearOpSourceBase<double>& fwdOpSrc) const override;
  Teuchos::RCP<Thyra::PreconditionerBase<double>> createPrec() const override;
  void initializePrec(const Teuchos::RCP<const Thyra::LinearOpSourceBase<double>>& fwdOpSrc,
                      Thyra::PreconditionerBase<double>* prec,
                      const Thyra::ESupportSolveUse supportSolveUse) const override;
  void uninitializePrec(Thyra::PreconditionerBase<double>* prec,
                        Teuchos::RCP<const Thyra::LinearOpSourceBase<double>>* fwdOpSrc,
                        Thyra::ESupportSolveUse* supportSolveUse) const override;

  void setParameterList(const Teuchos::RCP<Teuchos::ParameterList>& paramList) override;
  Teuchos::RCP<Teuchos::ParameterList> getNonconstParameterList() override;
  Teuchos::RCP<Teuchos::ParameterList> unsetParameterList() override;
  Teuchos::RCP<const Teuchos::ParameterList> getParameterList() const override;
  Teuchos::RCP<const Teuchos::ParameterList> getValidParameters() const override;
  std::string description() const override;

  const PreconditionerCounters& counters() const { return counters_; }

 private:
  Teuchos::RCP<Teuchos::ParameterList> params_;
  mutable PreconditionerCounters counters_;
};

}  // namespace traverse::solver
