// SPDX-License-Identifier: MIT
#include "core/solver/boundary.hpp"

#include <algorithm>
#include <cmath>

namespace fesph {

void applyFixedVelocities(Model& model) {
  Nodes& nd = model.nodes;
#pragma omp parallel for schedule(static)
  for (std::size_t a = 0; a < nd.size(); ++a) {
    const std::uint8_t bits = nd.fix[a];
    if (!bits) continue;
    for (int k = 0; k < 3; ++k)
      if (bits & (1u << k)) nd.v[a][k] = 0.0;
  }
}

namespace {

/// Particle i is to stay `offset` off the plane through `point` on the side `normal` points
/// to: its normal velocity is cut so that it ends the step there. One that starts closer (born
/// next to the plane) is only kept from coming closer: pushing it out within one step would
/// need a velocity of overlap/dt.
void holdOffPlane(Particles& pa, std::size_t i, const Vec3& point, const Vec3& normal,
                  double offset, double dt) {
  const double gap = (pa.x[i] - point).dot(normal) - offset;
  const double gap_next = gap + dt * pa.v[i].dot(normal);
  if (gap_next >= 0) return;
  const double target = std::min(gap, 0.0);  // end on the offset, or where it started
  if (gap_next < target) pa.v[i] += ((target - gap_next) / dt) * normal;
}

}  // namespace

void enforceRigidWalls(Model& model, double dt) {
  Nodes& nd = model.nodes;
  for (const RigidWall& w : model.walls) {
#pragma omp parallel for schedule(static)
    for (std::size_t a = 0; a < nd.size(); ++a) {
      if (nd.m[a] <= 0) continue;
      const double gap_next = (nd.x[a] + dt * nd.v[a] - w.point).dot(w.normal);
      if (gap_next >= 0) continue;
      // normal velocity change that lands the node exactly on the wall at the end of the step
      const double dvn = -gap_next / dt;
      Vec3 v = nd.v[a] + dvn * w.normal;
      if (w.friction > 0) {
        const Vec3 vt = v - v.dot(w.normal) * w.normal;
        const double vt_norm = vt.norm();
        if (vt_norm > 0) v -= std::min(1.0, w.friction * dvn / vt_norm) * vt;
      }
      nd.v[a] = v;
    }
    // Particles keep half their spacing cbrt(V) off the wall (frictionless).
    Particles& pa = model.particles;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < pa.size(); ++i)
      holdOffPlane(pa, i, w.point, w.normal, 0.5 * std::cbrt(pa.V[i]), dt);
  }
}

void enforceSymmetryPlanes(Model& model, double dt) {
  Particles& pa = model.particles;
  for (const SymmetryPlane& s : model.symmetry) {
    Vec3 point = Vec3::Zero();
    point[s.axis] = s.position;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < pa.size(); ++i) {
      const double d = pa.x[i][s.axis] - s.position;
      if (d == 0) continue;  // on the plane: its image is itself
      Vec3 normal = Vec3::Zero();
      normal[s.axis] = d > 0 ? 1.0 : -1.0;
      // A tenth of a spacing keeps its image a fifth of a spacing away: closer, the two
      // would be all but coincident particles, whose gradient (normalised by the pair's tiny
      // moment matrix when they have few other neighbours) grows as 1/distance. A quarter
      // spacing also stopped particles that the full model brings that close (a particle bar
      // through a particle plate: 0.1 % of the plastic work, test_symmetry_plane).
      holdOffPlane(pa, i, point, normal, 0.1 * std::cbrt(pa.V[i]), dt);
    }
  }
}

}  // namespace fesph
