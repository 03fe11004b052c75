// SPDX-License-Identifier: MIT
// Updated-Lagrangian SPH for solid particles: the material update and forces of every
// particle, within its own body, and the compression-only contact between particles of
// different bodies.
#pragma once

#include "core/state/model.hpp"

namespace fesph {

/// Bring every particle from t^{n-1} to t^n (positions x^n, velocities v^{n-1/2}; `dt_last`
/// = t^n - t^{n-1}, 0 at start): neighbours, corrected velocity gradient, density and h,
/// Jaumann/Johnson-Cook/EOS/damage update, artificial viscosity, and forces in
/// particles.f. Fills particles.dt (stable step estimates) and adds the particles' internal
/// energy to model.energy.internal (called after computeElementForces, which sets it).
void computeParticleForces(Model& model, double dt_last);

/// Particles of different bodies must not interpenetrate but never stick: momentum-conserving
/// velocity corrections on approaching pairs closer than their contact distance.
/// Their work is booked by the step (correctionWork).
void enforceParticleContact(Model& model, double dt);

/// The last step's pair stabilisation forces (SphWorkspace::pair_stab), recomputed from the
/// snapshot and pair gradients that step kept: the same bits as the step stored. For
/// checkpoints of format 2, which did not store them.
void restorePairStabilisation(Model& model);

}  // namespace fesph
