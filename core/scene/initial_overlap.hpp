// SPDX-License-Identifier: MIT
// Bodies that overlap at the start: a projectile placed inside a plate (a sign typo in its
// position) would be thrown out by the first contact passes with an impulse no experiment
// has, and the run would go on as if nothing had happened. A scene is refused instead.
#pragma once

#include "core/state/model.hpp"

#include <optional>

namespace fesph {

/// Points of one body (its nodes, or its particles) inside another body.
struct InitialOverlap {
  int inner = -1, outer = -1;   ///< body indices: inner's points lie inside outer's elements
  std::size_t points = 0;       ///< how many of inner's points do
  Vec3 example = Vec3::Zero();  ///< the first of them by index, m
};

/// The first pair of bodies, in body order (outer, then inner), of which one has points
/// inside the other: in one of its elements and on none of its exterior faces (to a
/// barycentric tolerance of 1e-9), so that bodies that only touch, face to face, pass.
/// Nothing when the bodies at most touch. Needs the model's surfaces (finaliseModel).
std::optional<InitialOverlap> findInitialOverlap(const Model& model);

}  // namespace fesph
