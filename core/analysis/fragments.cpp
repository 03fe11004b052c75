// SPDX-License-Identifier: MIT
#include "core/analysis/fragments.hpp"

#include "core/analysis/debris.hpp"
#include "core/common/union_find.hpp"
#include "core/state/model_build.hpp"

#include <algorithm>
#include <limits>

namespace fesph {

namespace {

bool madeOfParticles(const Body& b) { return b.discretisation == Discretisation::Sph; }

// The pieces of a body made of particles: its particles clumped as debris is (debris.hpp).
std::vector<Piece> particlePieces(const Model& model, int body) {
  const Particles& pa = model.particles;
  std::vector<int> ids;
  std::vector<DebrisParticle> list;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    if (pa.body[i] != body) continue;
    ids.push_back(static_cast<int>(i));
    list.push_back({pa.x[i], pa.v[i], pa.m[i], particleRadius(pa, i), 0.0, body});
  }
  std::vector<Piece> pieces;
  for (const Clump& c : findClumps(list)) {  // largest mass first
    Piece p;
    Vec3 momentum = Vec3::Zero();
    for (int k : c.members) {
      const int i = ids[static_cast<std::size_t>(k)];
      p.mass += pa.m[i];
      momentum += pa.m[i] * pa.v[i];
      p.centroid += pa.m[i] * pa.x[i];
      p.particles.push_back(i);
    }
    p.velocity = wholeVelocity(model, {}, momentum / p.mass, p.particles);
    p.centroid /= p.mass;
    pieces.push_back(std::move(p));
  }
  return pieces;
}

}  // namespace

double bodyInitialMass(const Model& model, int body) {
  const Body& b = model.bodies[body];
  double m = 0;
  for (std::size_t e = b.elem_begin; e < b.elem_end; ++e)
    m += model.materials[model.elems.material[e]].rho0 * model.elems.V0[e];
  if (madeOfParticles(b))
    for (std::size_t i = 0; i < model.particles.size(); ++i)
      if (model.particles.body[i] == body) m += model.particles.m[i];
  return m;
}

std::vector<Piece> bodyPieces(const Model& model, int body) {
  const Body& b = model.bodies[body];
  if (madeOfParticles(b)) return particlePieces(model, body);
  const Elements& el = model.elems;
  const Nodes& nd = model.nodes;
  UnionFind sets(nd.size());
  for (std::size_t e = b.elem_begin; e < b.elem_end; ++e) {
    if (el.status[e] != ElemStatus::Live) continue;
    for (int k = 1; k < 4; ++k) sets.join(el.conn[e][k], el.conn[e][0]);
  }
  std::vector<int> piece_of(nd.size(), -1);
  std::vector<Piece> pieces;
  for (std::size_t a = b.node_begin; a < b.node_end; ++a) {
    if (!(nd.m[a] > 0)) continue;
    const int r = sets.find(static_cast<int>(a));
    if (piece_of[r] < 0) {
      piece_of[r] = static_cast<int>(pieces.size());
      pieces.emplace_back();
    }
    Piece& p = pieces[piece_of[r]];
    p.mass += nd.m[a];
    p.velocity += nd.m[a] * nd.v[a];
    p.centroid += nd.m[a] * nd.x[a];
    p.nodes.push_back(static_cast<int>(a));
  }
  for (Piece& p : pieces) {
    p.velocity = wholeVelocity(model, p.nodes, p.velocity / p.mass);
    p.centroid /= p.mass;
  }
  std::stable_sort(pieces.begin(), pieces.end(),
                   [](const Piece& a, const Piece& b) { return a.mass > b.mass; });
  return pieces;
}

ResidualVelocity residualVelocity(const Model& model, int body) {
  ResidualVelocity r;
  const std::vector<Piece> pieces = bodyPieces(model, body);
  if (pieces.empty()) return r;
  const Piece& p = pieces.front();
  r.velocity = p.velocity;
  r.speed = p.velocity.norm();
  const double initial_mass = bodyInitialMass(model, body);
  r.mass_fraction = initial_mass > 0 ? p.mass / initial_mass : 0.0;
  if (!(r.speed > 0)) return r;
  const Vec3 dir = p.velocity / r.speed;
  double trailing = std::numeric_limits<double>::infinity();
  for (int a : p.nodes) trailing = std::min(trailing, model.nodes.x[a].dot(dir));
  for (int i : p.particles) trailing = std::min(trailing, model.particles.x[i].dot(dir));
  // Targets are the bodies that are not projectiles: a tandem's lead is not its follower's.
  double farthest_target = -std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < model.nodes.size(); ++a)
    if (!model.bodies[model.nodes.body[a]].is_projectile && model.nodes.m[a] > 0)
      farthest_target = std::max(farthest_target, model.nodes.x[a].dot(dir));
  // A target made of particles is its particles (those an element target's conversion makes
  // are its debris, not the target).
  const Particles& pa = model.particles;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    const Body& target = model.bodies[pa.body[i]];
    if (!target.is_projectile && madeOfParticles(target))
      farthest_target = std::max(farthest_target, pa.x[i].dot(dir));
  }
  r.cleared = trailing > farthest_target;
  return r;
}

}  // namespace fesph
