// SPDX-License-Identifier: MIT
// Element erosion, the plain-FEM baseline the paper compares against: a failed element is
// deleted, and its mass with its kinetic and internal energy are booked as lost.
#pragma once

#include "core/conversion/triggers.hpp"
#include "core/state/model.hpp"

namespace fesph {

/// Delete every live element whose trigger fires, in ascending element id. Its nodes each
/// lose a quarter of its mass (a node left without mass retires), its faces update the
/// exterior surfaces, and the energy it carried moves to the budget's eroded term.
/// Returns the number of elements deleted.
long erodeElements(Model& model);

/// Delete live element e for reason `why` (see erodeElements).
void erodeElement(Model& model, std::size_t e, Trigger why);

/// Remove live element e (Eroded or Converted): status, nodal masses, surfaces.
/// Returns the kinetic energy its share of the nodal masses carried at the last half step.
double retireElement(Model& model, std::size_t e, ElemStatus status);

}  // namespace fesph
