// SPDX-License-Identifier: MIT
// Particles on the wrong side of a half model's symmetry plane. The particles see their mirror
// images there and are kept on their side (docs/sph.md, "Symmetry planes"), so there should be
// none; a run reports the count as a check (runs before the mirror images had many).
#pragma once

#include "core/scene/scene.hpp"
#include "core/state/model.hpp"

#include <vector>

namespace fesph {

struct SymmetryLeak {
  const SymmetryPlane* plane = nullptr;
  long particles = 0;          ///< particles across the plane
  double mass = 0;             ///< their mass, kg
  double mass_fraction = 0;    ///< over the mass of all particles
};

/// For every plane: the particles on the side away from the model's nodes (the side the
/// nodes' mean position is not on). Planes with no node off them report nothing.
std::vector<SymmetryLeak> particlesAcrossSymmetry(const Model& model,
                                                  const std::vector<SymmetryPlane>& planes);

}  // namespace fesph
