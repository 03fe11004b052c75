// SPDX-License-Identifier: MIT
// A structured tetrahedral mesh of a box: each of nx*ny*nz cubes cut into 6 tets sharing the
// cube's main diagonal (Kuhn's subdivision), conforming across cubes. Used by tests and
// benchmarks, where a mesh must be cheap and exactly known.
#pragma once

#include "core/mesh/mesh.hpp"

namespace fesph {

/// Box [origin, origin + size] with nx, ny, nz cells per direction.
TetMesh structuredBox(const Vec3& origin, const Vec3& size, int nx, int ny, int nz);

}  // namespace fesph
