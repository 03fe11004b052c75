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

/// The plane of triangle (a, b, c): n = (b - a) x (c - a), |n|^2 and, for a triangle that is
/// not degenerate (valid()), the unit normal n / |n|.
struct FacePlane {
  Vec3 n = Vec3::Zero();
  double area2 = 0;  ///< |n|^2, (2 x area)^2
  Vec3 normal = Vec3::Zero();
  bool valid() const { return area2 > 0; }
};

inline FacePlane facePlane(const Vec3& a, const Vec3& b, const Vec3& c) {
  FacePlane f;
  f.n = (b - a).cross(c - a);
  f.area2 = f.n.squaredNorm();
  if (f.valid()) f.normal = f.n / std::sqrt(f.area2);
  return f;
}

/// Barycentric weights of q, a point in the plane f of triangle (a, b, c): the areas of the
/// sub-triangles opposite each vertex, signed against n.
inline Vec3 baryInPlane(const Vec3& q, const Vec3& a, const Vec3& b, const Vec3& c,
                        const FacePlane& f) {
  Vec3 w;
  w.x() = (b - q).cross(c - q).dot(f.n) / f.area2;
  w.y() = (c - q).cross(a - q).dot(f.n) / f.area2;
  w.z() = 1.0 - w.x() - w.y();
  return w;
}

/// Project p on the plane of triangle (a, b, c). Returns false for a degenerate triangle.
inline bool projectOnFace(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c,
                          FaceProjection& out) {
  const FacePlane f = facePlane(a, b, c);
  if (!f.valid()) return false;
  out.normal = f.normal;
  out.distance = (p - a).dot(out.normal);
  out.bary = baryInPlane(p - out.distance * out.normal, a, b, c, f);
  return true;
}

/// Nearest point of the triangle's barycentric range to `w`: clamp and renormalise.
inline Vec3 clampBary(Vec3 w) {
  w = w.cwiseMax(0.0);
  const double s = w.sum();
  return s > 0 ? Vec3(w / s) : Vec3(1.0 / 3, 1.0 / 3, 1.0 / 3);
}

}  // namespace fesph
