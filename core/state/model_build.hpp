// SPDX-License-Identifier: MIT
// Assembling a Model from meshed bodies: nodes, elements, lumped masses, the node ->
// element-corner lists, and the initial state.
#pragma once

#include "core/mesh/mesh.hpp"
#include "core/state/model.hpp"

#include <cmath>
#include <string>
#include <utility>
#include <vector>

namespace fesph {

/// Rigid placement of a body's local mesh: x = R x_local + translation.
struct Placement {
  Mat3 rotation = Mat3::Identity();
  Vec3 translation = Vec3::Zero();
};

/// Append a meshed body with uniform initial velocity. `materials`: one per region of the
/// mesh (TetMesh::region; one material when it has none). Returns the body index.
int addBody(Model& model, const std::string& name, const TetMesh& mesh,
            const std::vector<int>& materials, const Placement& placement, const Vec3& velocity,
            bool is_projectile);
inline int addBody(Model& model, const std::string& name, const TetMesh& mesh, int material,
                   const Placement& placement, const Vec3& velocity, bool is_projectile) {
  return addBody(model, name, mesh, std::vector<int>{material}, placement, velocity,
                 is_projectile);
}

/// The material of tet t of `mesh` read with one per region (addBody's `materials`); throws
/// std::logic_error when `materials` has no entry for its region.
int tetMaterial(const TetMesh& mesh, const std::vector<int>& materials, std::size_t t);

/// Lumped masses, corner lists, scratch arrays and the initial energy. Call once after all
/// bodies are added. Throws InputError for a degenerate mesh.
void finaliseModel(Model& model);

/// Append one particle (mass m, volume V, diameter at birth d0, smoothing length h).
/// Returns its index.
std::size_t appendParticle(Particles& pa, const Vec3& x, const Vec3& v, double m, double V,
                           double d0, double h, const PointState& st, int body, int material,
                           int parent);

/// Mass-weighted mean velocity of a body's active nodes and particles, m/s: that of the whole
/// body a half (or quarter) model's body stands for (wholeVelocity).
Vec3 bodyMeanVelocity(const Model& model, int body);

/// The velocity `v` of a part of a model with symmetry planes as the velocity of the whole it
/// stands for. A part a plane cuts is half of a part of the full model whose other half is its
/// mirror image, so its velocity normal to that plane cancels; a part off the plane has a twin
/// of its own and keeps `v`. A plane cuts the part when it holds one of the part's nodes
/// (`nodes`) or one of its particles (`particles`) lies within its smoothing length of the
/// plane (its mirror image is its neighbour); a body, when it holds one of the body's.
Vec3 wholeVelocity(const Model& model, const std::vector<int>& nodes, Vec3 v,
                   const std::vector<int>& particles = {});
Vec3 wholeBodyVelocity(const Model& model, int body, Vec3 v);

/// The symmetry planes that cut `body`, one bit per axis (1 << axis), as wholeBodyVelocity
/// finds them: for many velocities of one body, found once.
unsigned planesCutting(const Model& model, int body);
/// `v` with its components normal to the planes `planes` (bits as planesCutting's) zeroed.
Vec3 alongPlanes(Vec3 v, unsigned planes);

/// Mass of a body's active nodes and particles, kg.
double bodyMass(const Model& model, int body);

/// Bounding box (lower, upper corner) of a body's nodes, and of its particles for a body made
/// of them, m; lower > upper when it has neither.
std::pair<Vec3, Vec3> bodyExtent(const Model& model, int body);

/// Radius of particle i as the particle series draws it and debris clumps link it: half its
/// spacing cbrt(V), m.
inline double particleRadius(const Particles& pa, std::size_t i) {
  return 0.5 * std::cbrt(pa.V[i]);
}

}  // namespace fesph
