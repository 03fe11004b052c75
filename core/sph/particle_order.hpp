// SPDX-License-Identifier: MIT
// The particles' numbering. Converted particles are appended in the order their elements
// convert, so a particle's neighbours end up scattered over every particle array and each
// neighbour visit misses the cache: renumbering them in spatial order every few steps brings
// the SPH passes to the cost of a lattice (docs/performance.md, "The particles' order").
#pragma once

#include "core/state/model.hpp"

#include <vector>

namespace fesph {

/// The particles grouped by body, each body along a Morton (Z-order) curve through the
/// particles' bounding box, ties by index: order[k] is the particle that takes index k.
/// Deterministic: it depends on positions and bodies only.
std::vector<int> spatialOrder(const Particles& pa);

/// Give particle order[k] the index k in every particle array of the model (particles and
/// the SPH layer's last-step snapshot), and drop what the SPH layer keeps by index (the last
/// step's pair list, the Verlet candidates): the next step builds them afresh. The
/// snapshot must cover every particle (true between steps).
void renumberParticles(Model& model, const std::vector<int>& order);

/// renumberParticles(model, spatialOrder(...)) every SphControls::order_interval steps, when
/// there are particles and the SPH snapshot covers them; returns whether it renumbered.
bool orderParticlesIfDue(Model& model);

}  // namespace fesph
