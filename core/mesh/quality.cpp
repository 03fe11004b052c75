// SPDX-License-Identifier: MIT
// Mesh quality figures: shape quality, smallest dihedral angle and total volume of a tet mesh.
#include "core/mesh/mesh.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace fesph {
namespace {

/// q = 12 (3V)^(2/3) / sum(l^2); an inverted tet counts as q = 0 so that it shows up.
double shapeQuality(const std::array<Vec3, 4>& x) {
  const double v = std::max(tetVolume(x[0], x[1], x[2], x[3]), 0.0);
  double sum_l2 = 0.0;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j) sum_l2 += (x[j] - x[i]).squaredNorm();
  return 12.0 * std::cbrt(3.0 * v * 3.0 * v) / sum_l2;
}

/// Smallest of the six dihedral angles (rad): pi minus the angle between outward normals.
double minDihedral(const std::array<Vec3, 4>& x) {
  std::array<Vec3, 4> n;  // n[k]: normal of the face opposite node k
  for (int k = 0; k < 4; ++k) {
    const Vec3& a = x[(k + 1) % 4];
    const Vec3& b = x[(k + 2) % 4];
    const Vec3& c = x[(k + 3) % 4];
    n[k] = (b - a).cross(c - a).normalized();
    if (n[k].dot(x[k] - a) > 0.0) n[k] = -n[k];  // point away from the opposite node
  }
  double min_angle = M_PI;
  for (int i = 0; i < 4; ++i)
    for (int j = i + 1; j < 4; ++j)
      min_angle = std::min(min_angle, std::acos(std::clamp(-n[i].dot(n[j]), -1.0, 1.0)));
  return min_angle;
}

}  // namespace

MeshQuality meshQuality(const TetMesh& mesh) {
  MeshQuality q;
  q.nodes = mesh.nodes.size();
  q.elements = mesh.tets.size();
  if (mesh.tets.empty()) return q;
  q.min_quality = std::numeric_limits<double>::max();
  double min_dihedral = M_PI, sum_quality = 0.0;
  for (const auto& t : mesh.tets) {
    const std::array<Vec3, 4> x{mesh.nodes[t[0]], mesh.nodes[t[1]], mesh.nodes[t[2]],
                                mesh.nodes[t[3]]};
    const double shape = shapeQuality(x);
    q.min_quality = std::min(q.min_quality, shape);
    sum_quality += shape;
    min_dihedral = std::min(min_dihedral, minDihedral(x));
    q.volume += tetVolume(x[0], x[1], x[2], x[3]);
  }
  q.mean_quality = sum_quality / static_cast<double>(mesh.tets.size());
  q.min_dihedral_deg = min_dihedral * 180.0 / M_PI;
  return q;
}

}  // namespace fesph
