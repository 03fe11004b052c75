// SPDX-License-Identifier: MIT
// Kinematic boundary conditions on the half-step velocities: fixed components (fixed faces,
// symmetry planes) and rigid walls; particles at symmetry planes.
#pragma once

#include "core/state/model.hpp"

namespace fesph {

/// Zero every velocity component whose fix bit is set.
void applyFixedVelocities(Model& model);

/// Keep nodes on the allowed side of each rigid wall: a node that would end the step behind
/// the wall gets the normal velocity that puts it on the wall (frictionless, or with the
/// tangential change capped by Coulomb friction). Its work is booked by the step.
void enforceRigidWalls(Model& model, double dt);

/// Keep every particle on its side of each symmetry plane: one that would cross it in this
/// step gets the normal velocity that lands it on the plane. In the full model it would meet
/// its own mirror image there, head on. The mirror images' forces (sph_forces) keep particles
/// off the plane; this is the last resort. Its work is booked by the step.
void enforceSymmetryPlanes(Model& model, double dt);

}  // namespace fesph
