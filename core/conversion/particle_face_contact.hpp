// SPDX-License-Identifier: MIT
// Contact of SPH particles with the exterior element faces of every body (the paper's eqs.
// 1-5 with a particle as the slave): fragments of one plate strike the next plate, the
// projectile and the crater walls of their own plate.
#pragma once

#include "core/state/model.hpp"

namespace fesph {

/// Contact radius of a particle: a fraction of its spacing cbrt(V). 0.35 keeps a particle born
/// at the centroid of a regular tet (0.42 spacings from each face) clear of the faces around it.
inline constexpr double kParticleContactRadius = 0.35;

/// For every untied particle whose predicted position x + dt v ends closer than its contact
/// radius to (or behind) an exterior face that it started in front of, within the face:
/// dv_s = alpha (delta/dt) n / (1 + sum R_i^2 m_s/m_i), dv_i = -R_i (m_s/m_i) dv_s (momentum
/// conserved), N relaxed passes with alpha_k = 1/sqrt(N-k+1). Pushes apart only. A particle
/// that starts the step inside its contact radius is only kept from coming closer.
void enforceParticleFaceContact(Model& model, double dt, int passes);

/// Bytes held by the buffers enforceParticleFaceContact keeps from call to call on the calling
/// thread (the one stepping the model), for the memory figures of merit.
std::size_t particleFaceContactScratchBytes();

}  // namespace fesph
