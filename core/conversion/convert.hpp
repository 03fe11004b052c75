// SPDX-License-Identifier: MIT
// Adaptive FE -> SPH conversion (Hu, Sun & Zhu 2015 after Johnson et al. 2002/2003): an element
// whose trigger fires becomes one particle that keeps its mass, momentum and history.
#pragma once

#include "core/state/model.hpp"

namespace fesph {

/// Convert every live element whose trigger fires, in ascending element id, into one particle:
/// at the centroid, mass rho0 V0, velocity the mean of its 4 nodal velocities, the element's
/// stress, strain, rate, temperature, energy and damage, V and h = kappa cbrt(V), d0 = cbrt(V0).
/// Each node loses m_e/4 and keeps its velocity (mass and momentum conserved exactly); the
/// kinetic energy jump (m_e/8) sum |v_a - v_mean|^2 is booked as the conversion term. A particle
/// born on a face of a live element is tied to it. Returns the number of conversions.
long convertElements(Model& model, double kappa);

/// Convert (sph mode) or erode (erosion mode) live element e with its current state, counted
/// as a safety trigger. Returns false in a run without conversion or erosion.
bool retireInvertedElement(Model& model, std::size_t e);

}  // namespace fesph
