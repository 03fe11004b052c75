// SPDX-License-Identifier: MIT
// Pieces of a body (connected live elements; for a body made of particles, its linked
// particles) and the residual velocity of a projectile: the mass-weighted mean velocity of its
// largest intact piece, the one definition used everywhere.
#pragma once

#include "core/state/model.hpp"

#include <vector>

namespace fesph {

/// A connected set of live elements of one body (elements sharing a node are connected), or,
/// for a body made of particles from the start, a clump of its particles (linked as debris
/// clumps are: debris.hpp, DebrisOptions::link).
struct Piece {
  double mass = 0;              ///< kg, lumped masses of its nodes
  Vec3 velocity = Vec3::Zero();  ///< mass-weighted mean velocity of its nodes (wholeVelocity), m/s
  Vec3 centroid = Vec3::Zero();  ///< mass-weighted mean position, m
  std::vector<int> nodes;       ///< node ids, ascending (a piece of elements)
  std::vector<int> particles;   ///< particle ids, ascending (a piece of a body of particles)
};

/// Mass of `body` as built (rho0 V0 summed over all its elements, whatever their status; for a
/// body made of particles, its particles' masses, which never change), kg.
double bodyInitialMass(const Model& model, int body);

/// The pieces of `body`, largest mass first.
std::vector<Piece> bodyPieces(const Model& model, int body);

struct ResidualVelocity {
  double speed = 0;       ///< |velocity| of the largest piece, m/s
  Vec3 velocity = Vec3::Zero();
  double mass_fraction = 0;  ///< its mass over the body's initial mass
  bool cleared = false;   ///< its trailing point is past every target's nodes along the flight
};

/// Residual velocity of projectile `body`: its largest intact piece; `cleared` tells whether
/// that piece has passed every target (no node with mass of a body that is not a projectile,
/// nor a particle of one made of particles, lies ahead of the piece's trailing node or particle
/// along the piece's velocity; another projectile ahead, a tandem's lead, is no target).
ResidualVelocity residualVelocity(const Model& model, int body);

}  // namespace fesph
