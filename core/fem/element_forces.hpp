// SPDX-License-Identifier: MIT
// Internal forces of the linear tetrahedra: kinematics over the last interval, material
// update (Jaumann rate, strength, damage), volumetric response with average nodal pressure,
// bulk viscosity, corner forces and the deterministic per-node gather.
#pragma once

#include "core/state/model.hpp"

namespace fesph {

/// Bring every live element from t^{n-1} to t^n and assemble nodal forces at t^n.
/// Positions hold x^n and velocities v^{n-1/2}; `dt_last` is t^n - t^{n-1} (0 at start).
/// Also fills each element's stable time step estimate and the internal energy budget.
void computeElementForces(Model& model, double dt_last);

}  // namespace fesph
