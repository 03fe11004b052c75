// SPDX-License-Identifier: MIT
#include "core/mesh/untied_parts.hpp"

#include "core/mesh/tet_faces.hpp"

#include <algorithm>
#include <cmath>
#include <unordered_map>
#include <vector>

namespace fesph {

namespace {

// Faces that belong to one tet only: the parts' boundaries.
std::vector<TetFaceEntry> boundaryFaces(const TetMesh& mesh) {
  const std::vector<TetFaceEntry> faces = sortedTetFaces(mesh.tets);
  std::vector<TetFaceEntry> once;
  for (std::size_t i = 0; i < faces.size();) {
    std::size_t j = i + 1;
    while (j < faces.size() && faces[j].key == faces[i].key) ++j;
    if (j == i + 1) once.push_back(faces[i]);
    i = j;
  }
  return once;
}

// Smallest barycentric coordinate of p in the tet (>= 0: inside or on it).
double insideness(const TetMesh& mesh, int t, const Vec3& p) {
  const auto& c = mesh.tets[static_cast<std::size_t>(t)];
  const Vec3 &a = mesh.nodes[c[0]], &b = mesh.nodes[c[1]], &d = mesh.nodes[c[2]],
             &e = mesh.nodes[c[3]];
  const double V = tetVolume(a, b, d, e);
  return std::min({tetVolume(p, b, d, e), tetVolume(a, p, d, e), tetVolume(a, b, p, e),
                   tetVolume(a, b, d, p)}) / V;
}

}  // namespace

UntiedContact untiedParts(const TetMesh& mesh) {
  UntiedContact found;
  if (mesh.tets.empty()) return found;
  const std::vector<TetFaceEntry> boundary = boundaryFaces(mesh);
  // a grid of cells of the mean edge, each listing the tets whose box meets it
  double edge = 0;
  for (const auto& c : mesh.tets) edge += (mesh.nodes[c[0]] - mesh.nodes[c[1]]).norm();
  const double cell = edge / static_cast<double>(mesh.tets.size());
  const auto key = [](long long i, long long j, long long k) {
    return (i * 73856093LL) ^ (j * 19349663LL) ^ (k * 83492791LL);
  };
  const auto index = [&](double x) { return static_cast<long long>(std::floor(x / cell)); };
  std::unordered_map<long long, std::vector<int>> grid;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    Vec3 lo = mesh.nodes[mesh.tets[t][0]], hi = lo;
    for (int n : mesh.tets[t]) lo = lo.cwiseMin(mesh.nodes[n]), hi = hi.cwiseMax(mesh.nodes[n]);
    for (long long i = index(lo.x()); i <= index(hi.x()); ++i)
      for (long long j = index(lo.y()); j <= index(hi.y()); ++j)
        for (long long k = index(lo.z()); k <= index(hi.z()); ++k)
          grid[key(i, j, k)].push_back(static_cast<int>(t));
  }
  for (const TetFaceEntry& f : boundary) {
    const Vec3 centre =
        (mesh.nodes[f.key[0]] + mesh.nodes[f.key[1]] + mesh.nodes[f.key[2]]) / 3.0;
    const auto it = grid.find(key(index(centre.x()), index(centre.y()), index(centre.z())));
    if (it == grid.end()) continue;  // (a hash collision only adds candidates)
    for (int t : it->second) {
      if (t == f.tet || insideness(mesh, t, centre) < -0.01) continue;
      if (found.faces++ == 0) found.tet = f.tet, found.other = t, found.centre = centre;
      break;
    }
  }
  return found;
}

}  // namespace fesph
