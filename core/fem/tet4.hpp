// SPDX-License-Identifier: MIT
// Linear tetrahedron kinematics: volume, shape-function gradients, velocity gradient,
// smallest altitude. Constant-strain element, so everything is per element.
#pragma once

#include "core/common/types.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace fesph {

struct TetGeometry {
  double volume = 0;             ///< signed, m^3 (negative: inverted)
  std::array<Vec3, 4> grad;      ///< dN_a/dx, 1/m
};

/// Volume and shape-function gradients of the tet (a, b, c, d). With J = [b-a, c-a, d-a],
/// the rows of J^-1 are the gradients of N_b, N_c, N_d (cross products over det J), and the
/// gradients sum to zero because the shape functions sum to one.
/// `altitude` (if not null) receives the smallest altitude 3V / (largest face area), the
/// length that sets the tet's stable step. The cross products are twice the areas of the faces
/// at a, so only the face opposite a takes one of its own.
inline TetGeometry tetGeometry(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d,
                               double* altitude = nullptr) {
  const Vec3 e1 = b - a, e2 = c - a, e3 = d - a;
  const Vec3 c23 = e2.cross(e3), c31 = e3.cross(e1), c12 = e1.cross(e2);
  const double det = e1.dot(c23);
  TetGeometry g;
  g.volume = det / 6.0;
  const double inv = 1.0 / det;
  g.grad[1] = c23 * inv;
  g.grad[2] = c31 * inv;
  g.grad[3] = c12 * inv;
  g.grad[0] = -(g.grad[1] + g.grad[2] + g.grad[3]);
  if (altitude) {
    // sqrt is monotonic and correctly rounded: the root of the largest square is the largest
    // norm, bit for bit, for one sqrt instead of four
    const double a0 = (c - b).cross(d - b).squaredNorm();
    const double largest = std::max(std::max(a0, c23.squaredNorm()),
                                    std::max(c31.squaredNorm(), c12.squaredNorm()));
    *altitude = 3.0 * std::abs(g.volume) / (0.5 * std::sqrt(largest));
  }
  return g;
}

/// Velocity gradient L_ij = sum_a v_a,i dN_a/dx_j.
inline Mat3 velocityGradient(const std::array<Vec3, 4>& v, const std::array<Vec3, 4>& grad) {
  Mat3 L = Mat3::Zero();
  for (int a = 0; a < 4; ++a) L.noalias() += v[a] * grad[a].transpose();
  return L;
}

}  // namespace fesph
