// SPDX-License-Identifier: MIT
// One explicit central-difference step of the whole model, and the pieces it is made of.
#pragma once

#include "core/state/model.hpp"

namespace fesph {

/// Advance the model by one step, never past `t_stop` (an output time or the end time).
/// Reads top to bottom; holds no I/O.
void step(Model& model, double t_stop);

/// Stable time step: Courant factor times the smallest element estimate, growth capped, not
/// past t_stop. Records what limited it in model.dt_limiter.
double stableTimeStep(Model& model, double t_stop);

/// v^{n+1/2} = v^{n-1/2} + dt_avg f / m for every node with mass.
void integrateVelocities(Model& model, double dt_avg);

/// Work done by this step's velocity corrections (walls, contact, ties), J: negative when
/// they dissipate. Compares the velocities with model.v_node_free / v_particle_free.
double correctionWork(const Model& model, double dt_avg);

/// Energy budget at t^n (after the corrections of v^{n+1/2}, which dissipated `dissipated`).
void recordEnergyBudget(Model& model, double dissipated);

/// x^{n+1} = x^n + dt v^{n+1/2}.
void integratePositions(Model& model, double dt);

}  // namespace fesph
