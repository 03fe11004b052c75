// SPDX-License-Identifier: MIT
#include "core/mesh/structured_box.hpp"

#include <utility>

namespace fesph {

TetMesh structuredBox(const Vec3& origin, const Vec3& size, int nx, int ny, int nz) {
  TetMesh mesh;
  auto id = [&](int i, int j, int k) { return (k * (ny + 1) + j) * (nx + 1) + i; };
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i)
        mesh.nodes.push_back(origin + Vec3(size.x() * i / nx, size.y() * j / ny, size.z() * k / nz));
  // The 6 monotone paths from corner 0 to corner 7 of the unit cube (bit 0: x, 1: y, 2: z).
  static const int paths[6][3] = {{1, 2, 4}, {1, 4, 2}, {2, 1, 4}, {2, 4, 1}, {4, 1, 2}, {4, 2, 1}};
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        auto corner = [&](int bits) {
          return id(i + (bits & 1), j + ((bits >> 1) & 1), k + ((bits >> 2) & 1));
        };
        for (const auto& p : paths) {
          std::array<int, 4> t = {corner(0), corner(p[0]), corner(p[0] | p[1]), corner(7)};
          const Vec3& a = mesh.nodes[t[0]];
          if (tetVolume(a, mesh.nodes[t[1]], mesh.nodes[t[2]], mesh.nodes[t[3]]) < 0)
            std::swap(t[2], t[3]);
          mesh.tets.push_back(t);
        }
      }
  return mesh;
}

}  // namespace fesph
