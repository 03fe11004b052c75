// SPDX-License-Identifier: MIT
#include "core/state/model_build.hpp"

#include "core/common/error.hpp"
#include "core/common/heap_bytes.hpp"
#include "core/contact/surfaces.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace fesph {

int tetMaterial(const TetMesh& mesh, const std::vector<int>& materials, std::size_t t) {
  const std::size_t region = mesh.region.empty() ? 0 : static_cast<std::size_t>(mesh.region[t]);
  if (region >= materials.size())
    throw std::logic_error("tet " + std::to_string(t) + " is of region " +
                           std::to_string(region) + ", and " +
                           std::to_string(materials.size()) + " materials were given");
  return materials[region];
}

int addBody(Model& model, const std::string& name, const TetMesh& mesh,
            const std::vector<int>& materials, const Placement& placement, const Vec3& velocity,
            bool is_projectile) {
  Nodes& nd = model.nodes;
  Elements& el = model.elems;
  const int b = static_cast<int>(model.bodies.size());
  Body body;
  body.name = name;
  body.material = tetMaterial(mesh, materials, 0);
  body.is_projectile = is_projectile;
  body.node_begin = nd.size();
  body.elem_begin = el.size();

  for (const Vec3& p : mesh.nodes) {
    const Vec3 x = placement.rotation * p + placement.translation;
    nd.x.push_back(x);
    nd.x0.push_back(x);
    nd.v.push_back(velocity);
    nd.f.push_back(Vec3::Zero());
    nd.m.push_back(0.0);
    nd.body.push_back(b);
    nd.fix.push_back(0);
  }
  const int offset = static_cast<int>(body.node_begin);
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const int material = tetMaterial(mesh, materials, t);
    const Material& mat = model.materials.at(static_cast<std::size_t>(material));
    std::array<int, 4> c;
    for (int k = 0; k < 4; ++k) c[k] = mesh.tets[t][k] + offset;
    const double V = tetVolume(nd.x[c[0]], nd.x[c[1]], nd.x[c[2]], nd.x[c[3]]);
    if (!(V > 0))
      throw InputError("", 0, 0,
                       "body '" + name + "': tetrahedron " + std::to_string(t) +
                           " has non-positive volume " + std::to_string(V) + " m^3");
    el.conn.push_back(c);
    el.body.push_back(b);
    el.material.push_back(material);
    el.V0.push_back(V);
    el.V.push_back(V);
    el.dV.push_back(0.0);
    el.rho.push_back(mat.rho0);
    el.q.push_back(0.0);
    el.div_v.push_back(0.0);
    el.dt.push_back(0.0);
    el.len.push_back(0.0);
    el.len0.push_back(0.0);
    PointState st;
    st.T = mat.T_room;
    el.state.push_back(st);
    el.status.push_back(ElemStatus::Live);
  }
  body.node_end = nd.size();
  body.elem_end = el.size();
  model.bodies.push_back(body);
  return b;
}

void finaliseModel(Model& model) {
  Nodes& nd = model.nodes;
  const Elements& el = model.elems;
  std::fill(nd.m.begin(), nd.m.end(), 0.0);
  std::vector<std::size_t> count(nd.size() + 1, 0);
  for (std::size_t e = 0; e < el.size(); ++e) {
    const double me = model.materials[el.material[e]].rho0 * el.V0[e];
    for (int k = 0; k < 4; ++k) {
      nd.m[el.conn[e][k]] += 0.25 * me;
      ++count[el.conn[e][k] + 1];
    }
  }
  // CSR node -> corners, sorted by element id: the gather order is fixed.
  model.node_corner_offset.assign(nd.size() + 1, 0);
  for (std::size_t a = 0; a < nd.size(); ++a)
    model.node_corner_offset[a + 1] = model.node_corner_offset[a] + count[a + 1];
  model.node_corners.assign(model.node_corner_offset.back(), 0);
  std::vector<std::size_t> fill(model.node_corner_offset.begin(), model.node_corner_offset.end() - 1);
  for (std::size_t e = 0; e < el.size(); ++e)
    for (int k = 0; k < 4; ++k)
      model.node_corners[fill[el.conn[e][k]]++] = static_cast<std::uint32_t>(e * 4 + k);

  for (std::size_t a = 0; a < nd.size(); ++a)
    if (nd.m[a] <= 0)
      throw InputError("", 0, 0,
                       "node " + std::to_string(a) + " of body '" + model.bodies[nd.body[a]].name +
                           "' belongs to no tetrahedron");

  model.corner_force.assign(el.size(), {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()});
  model.nodal_volume_ratio.assign(nd.size(), 0.0);

  buildSurfaces(model);

  EnergyBudget& en = model.energy;
  en = EnergyBudget{};
  for (std::size_t a = 0; a < nd.size(); ++a) {
    en.kinetic_half += 0.5 * nd.m[a] * nd.v[a].squaredNorm();
    en.momentum += nd.m[a] * nd.v[a];
  }
  const Particles& pa = model.particles;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    en.kinetic_half += 0.5 * pa.m[i] * pa.v[i].squaredNorm();
    en.momentum += pa.m[i] * pa.v[i];
    en.internal += pa.m[i] * pa.state[i].e;
  }
  en.kinetic = en.kinetic_half;
  en.initial = en.total();
}

std::size_t appendParticle(Particles& pa, const Vec3& x, const Vec3& v, double m, double V,
                           double d0, double h, const PointState& st, int body, int material,
                           int parent) {
  const std::size_t i = pa.size();
  // grown by an eighth, not doubled, as particles are born a few at a time (resizeSnug)
  const auto add = [i](auto& array, const auto& value) {
    resizeSnug(array, i + 1);
    array[i] = value;
  };
  add(pa.x, x);
  add(pa.v, v);
  add(pa.f, Vec3(Vec3::Zero()));
  add(pa.m, m);
  add(pa.V, V);
  add(pa.rho, m / V);
  add(pa.h, h);
  add(pa.d0, d0);
  add(pa.dt, 0.0);
  add(pa.state, st);
  add(pa.body, body);
  add(pa.material, material);
  add(pa.parent, parent);
  add(pa.tie, Tie{});
  add(pa.id, static_cast<int>(i));  // no particle is ever removed
  return i;
}

Vec3 bodyMeanVelocity(const Model& model, int body) {
  const Body& b = model.bodies[body];
  Vec3 p = Vec3::Zero();
  double m = 0;
  for (std::size_t a = b.node_begin; a < b.node_end; ++a) {
    p += model.nodes.m[a] * model.nodes.v[a];
    m += model.nodes.m[a];
  }
  const Particles& pa = model.particles;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    if (pa.body[i] != body) continue;
    p += pa.m[i] * pa.v[i];
    m += pa.m[i];
  }
  return m > 0 ? wholeBodyVelocity(model, body, p / m) : Vec3::Zero();
}

namespace {

// Held on the plane normal to `axis` by its symmetry condition (a node held in every
// direction, a fixed rim, may lie anywhere).
bool heldOnPlane(const Nodes& nd, std::size_t a, int axis) {
  return (nd.fix[a] >> axis & 1u) && nd.fix[a] != 0b111;
}

}  // namespace

Vec3 alongPlanes(Vec3 v, unsigned planes) {
  for (int axis = 0; axis < 3; ++axis)
    if (planes >> axis & 1u) v[axis] = 0;
  return v;
}

Vec3 wholeVelocity(const Model& model, const std::vector<int>& nodes, Vec3 v,
                   const std::vector<int>& particles) {
  const Particles& pa = model.particles;
  unsigned planes = 0;
  for (const SymmetryPlane& s : model.symmetry)
    if (std::any_of(nodes.begin(), nodes.end(),
                    [&](int a) { return heldOnPlane(model.nodes, a, s.axis); }) ||
        std::any_of(particles.begin(), particles.end(), [&](int i) {
          return std::abs(pa.x[i][s.axis] - s.position) < pa.h[i];
        }))
      planes |= 1u << s.axis;
  return alongPlanes(v, planes);
}

unsigned planesCutting(const Model& model, int body) {
  const Body& b = model.bodies[body];
  const Particles& pa = model.particles;
  unsigned planes = 0;
  for (const SymmetryPlane& s : model.symmetry) {
    bool cut = false;
    for (std::size_t a = b.node_begin; a < b.node_end && !cut; ++a)
      cut = heldOnPlane(model.nodes, a, s.axis);
    for (std::size_t i = 0; i < pa.size() && !cut; ++i)
      cut = pa.body[i] == body && std::abs(pa.x[i][s.axis] - s.position) < pa.h[i];
    if (cut) planes |= 1u << s.axis;
  }
  return planes;
}

Vec3 wholeBodyVelocity(const Model& model, int body, Vec3 v) {
  return alongPlanes(v, planesCutting(model, body));
}

double bodyMass(const Model& model, int body) {
  const Body& b = model.bodies[body];
  double m = 0;
  for (std::size_t a = b.node_begin; a < b.node_end; ++a) m += model.nodes.m[a];
  const Particles& pa = model.particles;
  for (std::size_t i = 0; i < pa.size(); ++i)
    if (pa.body[i] == body) m += pa.m[i];
  return m;
}

std::pair<Vec3, Vec3> bodyExtent(const Model& model, int body) {
  const Body& b = model.bodies[body];
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (std::size_t a = b.node_begin; a < b.node_end; ++a) {
    lo = lo.cwiseMin(model.nodes.x[a]);
    hi = hi.cwiseMax(model.nodes.x[a]);
  }
  if (b.discretisation == Discretisation::Sph)
    for (std::size_t i = 0; i < model.particles.size(); ++i)
      if (model.particles.body[i] == body) {
        lo = lo.cwiseMin(model.particles.x[i]);
        hi = hi.cwiseMax(model.particles.x[i]);
      }
  return {lo, hi};
}

}  // namespace fesph
