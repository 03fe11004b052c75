// SPDX-License-Identifier: MIT
// Bodies made of SPH particles from the start (no nodes, no elements), and their mass-weighted
// mean position and velocity.
#pragma once

#include "core/mesh/mesh.hpp"
#include "core/sph/sph_workspace.hpp"
#include "core/state/model.hpp"
#include "core/state/model_build.hpp"

#include <string>
#include <vector>

namespace fesph {

/// Append a body of particles at `points` (m) with volumes `volumes` (m^3), density rho0 of
/// `material`, uniform velocity, d0 = cbrt(V) and h = kappa d0. Returns the body index.
/// Throws InputError for a non-positive volume.
int addParticleBody(Model& model, const std::string& name, const std::vector<Vec3>& points,
                    const std::vector<double>& volumes, int material, const Vec3& velocity,
                    bool is_projectile, double kappa = SphControls{}.kappa);

/// Append a body of particles, one per tetrahedron of `mesh` at its centroid with the tet's
/// volume (placed by `placement`), of the material of the tet's region (`materials`, as
/// addBody's). Returns the body index.
int addParticleBody(Model& model, const std::string& name, const TetMesh& mesh,
                    const std::vector<int>& materials, const Placement& placement,
                    const Vec3& velocity, bool is_projectile, double kappa = SphControls{}.kappa);
inline int addParticleBody(Model& model, const std::string& name, const TetMesh& mesh,
                           int material, const Placement& placement, const Vec3& velocity,
                           bool is_projectile, double kappa = SphControls{}.kappa) {
  return addParticleBody(model, name, mesh, std::vector<int>{material}, placement, velocity,
                         is_projectile, kappa);
}

/// Mass-weighted mean position of a body's particles, m.
Vec3 particleBodyCentre(const Model& model, int body);

}  // namespace fesph
