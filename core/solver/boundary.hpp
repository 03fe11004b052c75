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

/// Keep every particle on its side of each symmetry plane, a tenth of its spacing cbrt(V)
/// off it (or, born closer, no closer): in the full model it would meet its own mirror image
/// there head on. The images' forces (sph_forces) mostly do it; this is the last resort for
/// debris with few neighbours. Its work is booked by the step.
void enforceSymmetryPlanes(Model& model, double dt);

}  // namespace fesph
