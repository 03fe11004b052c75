// SPDX-License-Identifier: MIT
// The faces of a set of tetrahedra keyed by their nodes: the one walk that finds which faces
// two tets share and which bound the mesh (the contact's face table, the untied-parts check).
#pragma once

#include <array>
#include <vector>

namespace fesph {

/// Face k of tet `tet` (the face opposite its corner k), keyed by its node ids ascending.
struct TetFaceEntry {
  std::array<int, 3> key;
  int tet, k;
};

/// Every face of every tet, sorted by key and then by tet: the faces two tets share are
/// neighbours in the list, in tet order.
std::vector<TetFaceEntry> sortedTetFaces(const std::vector<std::array<int, 4>>& tets);

}  // namespace fesph
