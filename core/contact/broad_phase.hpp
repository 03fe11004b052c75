// SPDX-License-Identifier: MIT
// Contact search: which exterior faces of other bodies each slave node may meet during the
// step. A spatial hash over the faces' swept boxes, rebuilt every step; faces and slaves
// outside every other body's bounds stay out of it.
#pragma once

#include "core/state/model.hpp"

namespace fesph {

/// Fill model.surfaces.candidates for a step of length dt from the current x^n and v^{n+1/2}.
/// Slave nodes: the active (m > 0) nodes of every body's exterior faces, in body order.
/// A face f of another body is a candidate of slave node s when the box of the segment
/// [x_s, x_s + dt v_s] overlaps the box of the face's nodes at x^n and x^n + dt v^{n+1/2},
/// widened on every side by depth_tolerance times the face's longest edge at x^n (that
/// margin is kept in model.surfaces.scratch.face_tol for the narrow phase).
/// candidates.active lists the slaves with at least one candidate, ascending.
/// O(slaves + faces); each list ascending; identical for any thread count.
void findContactCandidates(Model& model, double dt, double depth_tolerance);

}  // namespace fesph
