// SPDX-License-Identifier: MIT
#include "core/sph/particle_body.hpp"

#include "core/common/error.hpp"

#include <cmath>

namespace fesph {

namespace {

// The particles at `points` of volumes `volumes`, point k of material materials[k]; the body's
// own material `body_material` (Body::material).
int appendParticleBody(Model& model, const std::string& name, const std::vector<Vec3>& points,
                       const std::vector<double>& volumes, const std::vector<int>& materials,
                       int body_material, const Vec3& velocity, bool is_projectile,
                       double kappa) {
  if (points.size() != volumes.size())
    throw InputError("", 0, 0, "body '" + name + "': " + std::to_string(points.size()) +
                                   " particle positions but " + std::to_string(volumes.size()) +
                                   " volumes");
  const int b = static_cast<int>(model.bodies.size());
  Body body;
  body.name = name;
  body.material = body_material;
  body.discretisation = Discretisation::Sph;
  body.is_projectile = is_projectile;
  body.node_begin = body.node_end = model.nodes.size();
  body.elem_begin = body.elem_end = model.elems.size();

  Particles& pa = model.particles;
  for (std::size_t k = 0; k < points.size(); ++k) {
    const double V = volumes[k];
    if (!(V > 0))
      throw InputError("", 0, 0, "body '" + name + "': particle " + std::to_string(k) +
                                     " has non-positive volume " + std::to_string(V) + " m^3");
    const Material& mat = model.materials.at(static_cast<std::size_t>(materials[k]));
    const double d = std::cbrt(V);
    PointState st;
    st.T = mat.T_room;
    appendParticle(pa, points[k], velocity, mat.rho0 * V, V, d, kappa * d, st, b, materials[k],
                   -1);
    pa.rho.back() = mat.rho0;  // exactly, not m / V
  }
  model.bodies.push_back(body);
  return b;
}

}  // namespace

int addParticleBody(Model& model, const std::string& name, const std::vector<Vec3>& points,
                    const std::vector<double>& volumes, int material, const Vec3& velocity,
                    bool is_projectile, double kappa) {
  model.materials.at(static_cast<std::size_t>(material));  // checked with no particle too
  return appendParticleBody(model, name, points, volumes,
                            std::vector<int>(points.size(), material), material, velocity,
                            is_projectile, kappa);
}

int addParticleBody(Model& model, const std::string& name, const TetMesh& mesh,
                    const std::vector<int>& materials, const Placement& placement,
                    const Vec3& velocity, bool is_projectile, double kappa) {
  std::vector<Vec3> points;
  std::vector<double> volumes;
  std::vector<int> point_materials;
  points.reserve(mesh.tets.size());
  volumes.reserve(mesh.tets.size());
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    std::array<Vec3, 4> x;
    for (int k = 0; k < 4; ++k)
      x[k] = placement.rotation * mesh.nodes[mesh.tets[t][k]] + placement.translation;
    volumes.push_back(tetVolume(x[0], x[1], x[2], x[3]));
    points.push_back(0.25 * (x[0] + x[1] + x[2] + x[3]));
    point_materials.push_back(tetMaterial(mesh, materials, t));
  }
  return appendParticleBody(model, name, points, volumes, point_materials,
                            tetMaterial(mesh, materials, 0), velocity, is_projectile, kappa);
}

Vec3 particleBodyCentre(const Model& model, int body) {
  const Particles& pa = model.particles;
  Vec3 s = Vec3::Zero();
  double m = 0;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    if (pa.body[i] != body) continue;
    s += pa.m[i] * pa.x[i];
    m += pa.m[i];
  }
  return m > 0 ? Vec3(s / m) : Vec3::Zero();
}

}  // namespace fesph
