// SPDX-License-Identifier: MIT
// Particles on the wrong side of a half model's symmetry plane. The plane holds the nodes on
// it, but particles get no constraint and no mirror neighbours there (docs/sph.md, "Symmetry
// planes"), so some cross it; a run reports how many, so that nobody reads past the defect.
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
