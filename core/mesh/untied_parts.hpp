// SPDX-License-Identifier: MIT
// Parts of one mesh that touch without sharing their nodes. A body's tets are tied where they
// share nodes; volumes meshed apart (in Gmsh, without a boolean fragment) touch face to face
// with nodes of their own, and since a body has no contact with itself they would pass
// through each other without a word.
#pragma once

#include "core/mesh/mesh.hpp"

#include <cstddef>

namespace fesph {

struct UntiedContact {
  std::size_t faces = 0;  ///< boundary faces that lie on another tet
  int tet = -1, other = -1;     ///< the first such face's tet and the tet it lies on
  Vec3 centre = Vec3::Zero();   ///< that face's centroid, in the mesh's frame
};

/// Boundary faces of `mesh` (faces of one tet only) whose centroid lies in or on another tet,
/// within a hundredth of that tet's height (a chord of a curved face meshed twice lies that
/// close): parts meshed apart that touch, or overlap. None for a conformal mesh.
UntiedContact untiedParts(const TetMesh& mesh);

}  // namespace fesph
