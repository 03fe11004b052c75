// SPDX-License-Identifier: MIT
// Building and updating the exterior surfaces of the element bodies (Model::surfaces): the
// face table, the oriented exterior faces and the slave nodes of every body.
#pragma once

#include "core/state/model.hpp"

#include <array>
#include <cstddef>

namespace fesph {

/// Node ids of face k (opposite corner k) of a positively oriented tet, ordered so that
/// (x1 - x0) x (x2 - x0) points away from corner k.
inline std::array<int, 3> tetFace(const std::array<int, 4>& c, int k) {
  static const int local[4][3] = {{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}};
  return {c[local[k][0]], c[local[k][1]], c[local[k][2]]};
}

/// Face table and exterior surfaces from scratch, from the current element status. Call once
/// after finaliseModel. Throws InputError if more than two elements share a face.
void buildSurfaces(Model& model);

/// Update after element e stopped being Live (eroded or converted): its faces shared with a
/// live neighbour become exterior faces of the neighbour, its exterior faces disappear.
/// O(1) per face; calling it again for the same element changes nothing.
void removeElementFromSurfaces(Model& model, std::size_t e);

/// Index in model.surfaces.table of the face with these nodes (any order), -1 if none.
int findFace(const Surfaces& surfaces, int a, int b, int c);

}  // namespace fesph
