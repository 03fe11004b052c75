// SPDX-License-Identifier: MIT
// Orientation and compact renumbering shared by the Gmsh mesher and the .msh reader.
#include "core/mesh/tet_assembly.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

namespace fesph::mesh_detail {

bool isFlatTet(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d) {
  const double l2 = std::max({(b - a).squaredNorm(), (c - a).squaredNorm(),
                              (d - a).squaredNorm(), (c - b).squaredNorm(),
                              (d - b).squaredNorm(), (d - c).squaredNorm()});
  // Relative to the tet's own size, so the test does not depend on the units of the mesh.
  return std::abs(6.0 * tetVolume(a, b, c, d)) <= 1e-12 * l2 * std::sqrt(l2);
}

TetMesh assembleTetMesh(const std::vector<Vec3>& nodes, std::vector<std::array<int, 4>> tets) {
  std::vector<int> new_id(nodes.size(), -1);
  for (auto& t : tets) {
    if (tetVolume(nodes[t[0]], nodes[t[1]], nodes[t[2]], nodes[t[3]]) < 0.0)
      std::swap(t[2], t[3]);
    for (int n : t) new_id[n] = 0;
  }
  TetMesh mesh;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    if (new_id[i] < 0) continue;
    new_id[i] = static_cast<int>(mesh.nodes.size());
    mesh.nodes.push_back(nodes[i]);
  }
  for (auto& t : tets)
    for (int& n : t) n = new_id[n];
  mesh.tets = std::move(tets);
  return mesh;
}

}  // namespace fesph::mesh_detail
