// SPDX-License-Identifier: MIT
#include "core/conversion/particle_face_contact.hpp"

#include "core/conversion/face_geometry.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <unordered_map>

namespace fesph {

namespace {

double inverseMass(const Nodes& nd, int a) {
  return nd.fix[a] == 0b111 || !(nd.m[a] > 0) ? 0.0 : 1.0 / nd.m[a];
}

// Uniform hash grid of the exterior faces' swept boxes (start and predicted end positions,
// inflated by the largest contact radius and particle travel). A particle only needs the
// faces of the cell its predicted position falls in.
struct FaceGrid {
  double cell = 0;
  std::unordered_map<std::int64_t, std::vector<int>> cells;

  static std::int64_t key(long i, long j, long k) {
    return (static_cast<std::int64_t>(i) * 73856093) ^ (static_cast<std::int64_t>(j) * 19349663) ^
           (static_cast<std::int64_t>(k) * 83492791);
  }
  std::int64_t keyOf(const Vec3& p) const {
    return key(std::lround(std::floor(p.x() / cell)), std::lround(std::floor(p.y() / cell)),
               std::lround(std::floor(p.z() / cell)));
  }
};

FaceGrid buildGrid(const Model& model, double dt, double reach) {
  const Nodes& nd = model.nodes;
  const auto& faces = model.surfaces.exterior;
  FaceGrid g;
  double largest = 0;
  for (const ExteriorFace& f : faces)
    for (int i = 0; i < 3; ++i)
      largest = std::max(largest, (nd.x[f.node[i]] - nd.x[f.node[(i + 1) % 3]]).norm());
  g.cell = std::max(largest, 2 * reach);
  for (std::size_t k = 0; k < faces.size(); ++k) {
    Vec3 lo = Vec3::Constant(1e300), hi = Vec3::Constant(-1e300);
    for (int a : faces[k].node) {
      lo = lo.cwiseMin(nd.x[a]).cwiseMin(nd.x[a] + dt * nd.v[a]);
      hi = hi.cwiseMax(nd.x[a]).cwiseMax(nd.x[a] + dt * nd.v[a]);
    }
    lo.array() -= reach;
    hi.array() += reach;
    const long i0 = std::lround(std::floor(lo.x() / g.cell)), i1 = std::lround(std::floor(hi.x() / g.cell));
    const long j0 = std::lround(std::floor(lo.y() / g.cell)), j1 = std::lround(std::floor(hi.y() / g.cell));
    const long k0 = std::lround(std::floor(lo.z() / g.cell)), k1 = std::lround(std::floor(hi.z() / g.cell));
    for (long i = i0; i <= i1; ++i)
      for (long j = j0; j <= j1; ++j)
        for (long l = k0; l <= k1; ++l) g.cells[FaceGrid::key(i, j, l)].push_back(static_cast<int>(k));
  }
  return g;
}

struct Hit {
  int face = -1;
  double delta = 0;  ///< how far inside the contact radius the particle would end, m
  Vec3 normal = Vec3::Zero();
  Vec3 bary = Vec3::Zero();
};

// The face particle p penetrates most at the end of the step, if any.
Hit deepestHit(const Model& model, std::size_t p, const std::vector<int>& candidates, double dt) {
  const Nodes& nd = model.nodes;
  const Particles& pa = model.particles;
  const auto& faces = model.surfaces.exterior;
  const double radius = kParticleContactRadius * std::cbrt(pa.V[p]);
  const Vec3 xp = pa.x[p] + dt * pa.v[p];
  Hit best;
  for (int k : candidates) {
    const ExteriorFace& f = faces[k];
    Vec3 xe[3], x0[3];
    for (int i = 0; i < 3; ++i) x0[i] = nd.x[f.node[i]], xe[i] = x0[i] + dt * nd.v[f.node[i]];
    FaceProjection now, end;
    if (!projectOnFace(pa.x[p], x0[0], x0[1], x0[2], now) ||
        !projectOnFace(xp, xe[0], xe[1], xe[2], end))
      continue;
    // It must start in front of the face (a particle already behind it crossed elsewhere)
    // and end within the face's extent.
    if (now.distance < -radius) continue;
    if (end.bary.minCoeff() < -0.05) continue;
    // A particle already inside its radius (born next to faces, or left there by earlier
    // steps) is only kept from coming closer: pushing it out in one step would need a velocity
    // of overlap/dt and throw it away.
    if (end.distance >= radius) continue;
    const double delta =
        now.distance >= radius ? radius - end.distance : now.distance - end.distance;
    if (delta <= 0 || delta <= best.delta) continue;
    best = Hit{k, delta, end.normal, clampBary(end.bary)};
  }
  return best;
}

}  // namespace

void enforceParticleFaceContact(Model& model, double dt, int passes) {
  Particles& pa = model.particles;
  Nodes& nd = model.nodes;
  const auto& faces = model.surfaces.exterior;
  if (pa.size() == 0 || faces.empty() || !(dt > 0)) return;

  double reach = 0;
  for (std::size_t p = 0; p < pa.size(); ++p)
    reach = std::max(reach, kParticleContactRadius * std::cbrt(pa.V[p]) + dt * pa.v[p].norm());
  const FaceGrid grid = buildGrid(model, dt, reach);
  static const std::vector<int> none;

  for (int k = 1; k <= passes; ++k) {
    const double alpha = 1.0 / std::sqrt(static_cast<double>(passes - k + 1));
    bool any = false;
    // Sequential in particle order: particles share face nodes, the order must be fixed.
    for (std::size_t p = 0; p < pa.size(); ++p) {
      if (pa.tie[p].active()) continue;
      const auto it = grid.cells.find(grid.keyOf(pa.x[p] + dt * pa.v[p]));
      const Hit hit = deepestHit(model, p, it == grid.cells.end() ? none : it->second, dt);
      if (hit.face < 0) continue;
      const ExteriorFace& f = faces[hit.face];
      double denom = 1.0 / pa.m[p];
      for (int i = 0; i < 3; ++i) denom += hit.bary[i] * hit.bary[i] * inverseMass(nd, f.node[i]);
      const double impulse = alpha * hit.delta / dt / denom;
      pa.v[p] += (impulse / pa.m[p]) * hit.normal;
      for (int i = 0; i < 3; ++i) {
        Vec3 dv = (-hit.bary[i] * impulse * inverseMass(nd, f.node[i])) * hit.normal;
        for (int c = 0; c < 3; ++c)
          if (nd.fix[f.node[i]] & (1u << c)) dv[c] = 0.0;
        nd.v[f.node[i]] += dv;
      }
      any = true;
    }
    if (!any) break;
  }
}

}  // namespace fesph
