// SPDX-License-Identifier: MIT
#include "core/conversion/ties.hpp"

#include "core/contact/surfaces.hpp"
#include "core/common/omp_threads.hpp"
#include "core/common/thread_buffer.hpp"
#include "core/conversion/face_geometry.hpp"

#include <cmath>
#include <vector>

namespace fesph {

void tieToExposedFace(Model& model, std::size_t p, std::size_t e) {
  const Surfaces& s = model.surfaces;
  Particles& pa = model.particles;
  for (int k = 0; k < 4; ++k) {
    const FaceRecord& rec = s.table[s.elem_faces[e][k]];
    if (rec.exterior < 0) continue;
    const ExteriorFace& f = s.exterior[rec.exterior];
    const Nodes& nd = model.nodes;
    FaceProjection proj;
    if (!projectOnFace(pa.x[p], nd.x[f.node[0]], nd.x[f.node[1]], nd.x[f.node[2]], proj)) continue;
    pa.tie[p].face = f.node;
    pa.tie[p].bary = clampBary(proj.bary);
    return;
  }
}

long releaseTies(Model& model) {
  Particles& pa = model.particles;
  const long np = static_cast<long>(pa.size());
  long released = 0;
  // Tied particles gather in some stretches of the numbering (those converted next to live
  // elements): chunks taken as they come keep both threads busy; the count is the same.
#pragma omp parallel for schedule(dynamic, 256) reduction(+ : released) if (np > 32)
  for (long p = 0; p < np; ++p) {
    Tie& t = pa.tie[p];
    if (!t.active()) continue;
    const int f = findFace(model.surfaces, t.face[0], t.face[1], t.face[2]);
    const bool face_gone = f < 0 || model.surfaces.table[f].exterior < 0;
    if (face_gone || pa.state[p].damage >= 1.0) {
      t = Tie{};
      ++released;
    }
  }
  return released;
}

void enforceTies(Model& model, int passes) {
  Particles& pa = model.particles;
  Nodes& nd = model.nodes;
  // The tied particles, ascending, found once for all passes: each thread lists a contiguous
  // share (a static schedule deals them out in thread order), joined in that order. Every
  // pass scanned every particle's tie before, serially (0.4 % of an FE-SPH run). Parallel
  // from releaseTies' 32 particles on, so that the determinism test's few dozen split too.
  const long np = static_cast<long>(pa.size());
  std::vector<ThreadBuffer<std::vector<int>>> shares(static_cast<std::size_t>(maxThreads()));
#pragma omp parallel if (np > 32)
  {
    std::vector<int>& mine = shares[static_cast<std::size_t>(threadId())].items;
#pragma omp for schedule(static)
    for (long p = 0; p < np; ++p)
      if (pa.tie[p].active()) mine.push_back(static_cast<int>(p));
  }
  std::vector<int> tied;
  for (const auto& share : shares) tied.insert(tied.end(), share.items.begin(), share.items.end());

  for (int k = 1; k <= passes; ++k) {
    const double alpha = 1.0 / std::sqrt(static_cast<double>(passes - k + 1));
    // Sequential in particle order: ties share face nodes, so the order must be fixed.
    for (const int p : tied) {
      const Tie& t = pa.tie[p];
      Vec3 v_face = Vec3::Zero();
      double denom = 1.0;
      for (int i = 0; i < 3; ++i) {
        v_face += t.bary[i] * nd.v[t.face[i]];
        denom += t.bary[i] * t.bary[i] * pa.m[p] * nd.inverseMass(t.face[i]);
      }
      const Vec3 dv_s = -alpha * (pa.v[p] - v_face) / denom;
      pa.v[p] += dv_s;
      for (int i = 0; i < 3; ++i)
        nd.addVelocity(t.face[i], (-t.bary[i] * pa.m[p] * nd.inverseMass(t.face[i])) * dv_s);
    }
  }
}

}  // namespace fesph
