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
    // Particles keep half their spacing cbrt(V) off the wall (frictionless). One that starts
    // closer (born from an element on the wall) is only kept from coming closer: pushing it
    // out within one step would need a velocity of overlap/dt.
    Particles& pa = model.particles;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < pa.size(); ++i) {
      const double offset = 0.5 * std::cbrt(pa.V[i]);
      const double gap = (pa.x[i] - w.point).dot(w.normal) - offset;
      const double gap_next = gap + dt * pa.v[i].dot(w.normal);
      if (gap_next >= 0) continue;
      const double target = std::min(gap, 0.0);  // end on the offset, or where it started
      if (gap_next < target) pa.v[i] += ((target - gap_next) / dt) * w.normal;
    }
  }
}

void enforceSymmetryPlanes(Model& model, double dt) {
  Particles& pa = model.particles;
  for (const SymmetryPlane& s : model.symmetry) {
    const int a = s.axis;
#pragma omp parallel for schedule(static)
    for (std::size_t i = 0; i < pa.size(); ++i) {
      const double d = pa.x[i][a] - s.position, d_next = d + dt * pa.v[i][a];
      if ((d > 0 && d_next < 0) || (d < 0 && d_next > 0)) pa.v[i][a] = -d / dt;
    }
  }
}

}  // namespace fesph
