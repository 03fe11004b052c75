// SPDX-License-Identifier: MIT
// Internal to core/mesh: turns raw nodes and tets (from Gmsh or a .msh file) into a TetMesh
// with positive orientation and compact numbering.
#pragma once

#include "core/mesh/mesh.hpp"

namespace fesph::mesh_detail {

/// True when the tet is flat to round-off: |6V| <= 1e-12 * (longest edge)^3.
bool isFlatTet(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d);

/// Orients every tet positively (swapping its last two nodes when det < 0) and drops the
/// nodes no tet uses; the remaining nodes keep their relative order.
TetMesh assembleTetMesh(const std::vector<Vec3>& nodes, std::vector<std::array<int, 4>> tets);

}  // namespace fesph::mesh_detail
