#pragma once
// The parameter lists of traverse (core/param_list.hpp) where a Trilinos package takes a
// Teuchos::ParameterList (NOX, Stratimikos, LOCA, Anasazi): the same names, values and
// sublists in the same order; lists of numbers and words become Teuchos::Array.
#include <Teuchos_ParameterList.hpp>

#include "traverse/core/param_list.hpp"

namespace traverse::solver {

Teuchos::ParameterList to_teuchos(const ParamList& list);

/// The reverse, for the values a ParamList holds (bool, int, double, std::string,
/// Teuchos::Array of double or std::string); std::invalid_argument naming the key otherwise.
ParamList from_teuchos(const Teuchos::ParameterList& list);

}  // namespace traverse::solver
