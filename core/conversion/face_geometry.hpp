// SPDX-License-Identifier: MIT
// A point against a triangle: projection, barycentric weights and signed distance. Shared by
// particle-face contact and ties.
#pragma once

#include "core/common/types.hpp"

namespace fesph {

struct FaceProjection {
  Vec3 normal = Vec3::Zero();  ///< unit, (b - a) x (c - a) direction
  Vec3 bary = Vec3::Zero();    ///< barycentric weights of the projection (sum 1)
  double distance = 0;         ///< signed distance of the point along the normal, m
};

/// Project p on the plane of triangle (a, b, c). Returns false for a degenerate triangle.
inline bool projectOnFace(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                          FaceProjection& out) {
  const Vec3 n = (b - a).cross(c - a);
  const double area2 = n.squaredNorm();
  if (!(area2 > 0)) return false;
  out.normal = n / std::sqrt(area2);
  out.distance = (p - a).dot(out.normal);
  const Vec3 q = p - out.distance * out.normal;
  // areas of the sub-triangles opposite each vertex, signed against n
  out.bary.x() = (b - q).cross(c - q).dot(n) / area2;
  out.bary.y() = (c - q).cross(a - q).dot(n) / area2;
  out.bary.z() = 1.0 - out.bary.x() - out.bary.y();
  return true;
}

/// The signed distance of p from the plane of triangle (a, b, c) alone, with projectOnFace's
/// operations (same bits). Returns false for a degenerate triangle.
inline bool distanceToFace(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                           double& distance) {
  const Vec3 n = (b - a).cross(c - a);
  const double area2 = n.squaredNorm();
  if (!(area2 > 0)) return false;
  distance = (p - a).dot(n / std::sqrt(area2));
  return true;
}

/// Nearest point of the triangle's barycentric range to `w`: clamp and renormalise.
inline Vec3 clampBary(Vec3 w) {
  w = w.cwiseMax(0.0);
  const double s = w.sum();
  return s > 0 ? Vec3(w / s) : Vec3(1.0 / 3, 1.0 / 3, 1.0 / 3);
}

}  // namespace fesph
