// SPDX-License-Identifier: MIT
// Symmetric kinematic node-to-face contact between element bodies: momentum-conserving
// velocity corrections of Johnson & Stryk (2001), the paper's eqs. 1-5, on v^{n+1/2}.
#pragma once

#include "core/state/model.hpp"

namespace fesph {

/// Remove the penetrations of exterior faces of other bodies that the velocities v^{n+1/2}
/// would make over the step of length dt: every slave node (the nodes of every body's
/// exterior faces) whose predicted position x + dt v ends behind a face that it started in
/// front of, within the face, by delta, gets
///   dv_s = alpha (delta/dt) n / (1 + sum_i R_i^2 m_s/m_i),  dv_i = -R_i (m_s/m_i) dv_s
/// (n: the face's outward normal, R_i: barycentric weights of the projection), so total
/// momentum is unchanged. A node that starts behind the face by less than the depth
/// tolerance is kept from going deeper (delta = how much deeper it would go). A slave takes
/// the face it moves into fastest. N passes, alpha_k = 1/sqrt(N-k+1), each body the slave
/// side in turn in every pass. Surfaces only ever get pushed apart; friction caps the
/// tangential change at mu |dv_n|. The work of the corrections is booked by the step
/// (correctionWork). Needs model.surfaces (buildSurfaces). The same result for any thread
/// count.
void enforceNodeFaceContact(Model& model, double dt, const ContactControls& controls);

}  // namespace fesph
