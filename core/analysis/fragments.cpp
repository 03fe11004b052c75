// SPDX-License-Identifier: MIT
#include "core/analysis/fragments.hpp"

#include "core/common/union_find.hpp"
#include "core/state/model_build.hpp"

#include <algorithm>
#include <limits>

namespace fesph {

double bodyInitialMass(const Model& model, int body) {
  const Body& b = model.bodies[body];
  double m = 0;
  for (std::size_t e = b.elem_begin; e < b.elem_end; ++e)
    m += model.materials[model.elems.material[e]].rho0 * model.elems.V0[e];
  return m;
}

std::vector<Piece> bodyPieces(const Model& model, int body) {
  const Body& b = model.bodies[body];
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
  // Targets are the bodies that are not projectiles: a tandem's lead is not its follower's.
  double farthest_target = -std::numeric_limits<double>::infinity();
  for (std::size_t a = 0; a < model.nodes.size(); ++a)
    if (!model.bodies[model.nodes.body[a]].is_projectile && model.nodes.m[a] > 0)
      farthest_target = std::max(farthest_target, model.nodes.x[a].dot(dir));
  r.cleared = trailing > farthest_target;
  return r;
}

}  // namespace fesph
