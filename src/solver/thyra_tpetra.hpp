#pragma once
// The Thyra-over-Tpetra type names the solver module's sources share (private header).
#include <Thyra_ModelEvaluatorBase.hpp>
#include <Thyra_TpetraThyraWrappers.hpp>

#include "traverse/mesh/distributed_mesh.hpp"

namespace traverse::solver::tt {

using MEB = Thyra::ModelEvaluatorBase;
using LO = mesh::LO;
using GO = mesh::GO;
using Node = mesh::Map::node_type;
/// Tpetra objects inside Thyra wrappers (vectors, operators).
using Extract = Thyra::TpetraOperatorVectorExtraction<double, LO, GO, Node>;

}  // namespace traverse::solver::tt
