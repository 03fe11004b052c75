// SPDX-License-Identifier: MIT
// Coupling of particles to the element faces they were born on (the paper's eqs. 6-12, after
// Johnson 1994): momentum-conserving velocity corrections that keep a tied particle moving
// with its point on the face.
#pragma once

#include "core/state/model.hpp"

namespace fesph {

/// Tie particle p (just converted from element e) to the first face of e, in face order, that
/// now bounds a live element; its barycentric point is the particle's projection on it.
/// Leaves the particle untied when e had no live neighbour.
void tieToExposedFace(Model& model, std::size_t p, std::size_t e);

/// Release ties whose face is no longer exterior (its element converted or eroded) or whose
/// particle is fully damaged. Returns the number released.
long releaseTies(Model& model);

/// Make every tied particle move with its point on the face: N relaxed passes
/// (alpha_k = 1/sqrt(N-k+1)) of dv_s = -alpha v_rel / (1 + sum R_i^2 m_s/m_i),
/// dv_i = -R_i (m_s/m_i) dv_s, with v_rel = v_s - sum R_i v_i. Momentum is conserved.
void enforceTies(Model& model, int passes);

}  // namespace fesph
