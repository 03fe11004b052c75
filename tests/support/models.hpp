// SPDX-License-Identifier: MIT
// Small models built in code for the solver tests.
#pragma once

#include "core/mesh/structured_box.hpp"
#include "core/state/model_build.hpp"

#include <stdexcept>
#include <vector>

namespace fesph::testing {

/// Linear elastic material with a linear EOS (no strength model, no damage).
inline Material elasticMaterial(double rho = 7850, double E = 200e9, double nu = 0.3) {
  Material m;
  m.name = "elastic";
  m.rho0 = rho;
  m.E = E;
  m.nu = nu;
  m.strength = StrengthModel::Elastic;
  m.eos = EosModel::Linear;
  const std::string err = finaliseMaterial(m);
  if (!err.empty()) throw std::logic_error(err);
  return m;
}

/// elasticMaterial with a Mie-Grueneisen EOS (steel: c0 4570 m/s, s 1.49, Gamma0 1.93).
inline Material mieGruneisenSteel() {
  Material m = elasticMaterial();
  m.eos = EosModel::MieGruneisen;
  m.c0 = 4570, m.s = 1.49, m.gamma0 = 1.93;
  const std::string err = finaliseMaterial(m);
  if (!err.empty()) throw std::logic_error(err);
  return m;
}

/// elasticMaterial made elastic-perfectly plastic: Johnson-Cook with A = 300 MPa and no
/// hardening, rate dependence or heating (no specific heat).
inline Material perfectlyPlasticMaterial() {
  Material m = elasticMaterial();
  m.strength = StrengthModel::JohnsonCook;
  m.A = 300e6;
  const std::string err = finaliseMaterial(m);
  if (!err.empty()) throw std::logic_error(err);
  return m;
}

/// The deviatoric stress of perfectlyPlasticMaterial-like `mat` on its yield surface in
/// uniaxial compression along z: s_zz = -2A/3, s_xx = s_yy = A/3 (von Mises A).
inline Sym yieldedInUniaxialCompression(const Material& mat) {
  return Sym{mat.A / 3, mat.A / 3, -2 * mat.A / 3, 0, 0, 0};
}

/// Plastic work (J) of a volume V0 of perfectlyPlasticMaterial-like `mat` (yield stress A)
/// compressed in uniaxial strain z = z0 (1 - r t) from 0 to t_end, starting on its yield
/// surface (yieldedInUniaxialCompression), by hand: its equivalent strain rate is
/// (2/3) r / (1 - r t) and its volume V0 (1 - r t), so the plastic power A eps_p' V is the
/// constant (2/3) A r V0.
inline double uniaxialPlasticWork(const Material& mat, double r, double V0, double t_end) {
  return 2.0 / 3.0 * mat.A * r * V0 * t_end;
}

/// Specific internal energy (J/kg) of a point of `mat` compressed without dissipation from
/// (1/rho0, e = 0) to the specific volume v1 (m^3/kg): de = -p(1/v, e) dv integrated with RK4
/// in 4000 steps, converged far below what the energy-order tests check.
inline double adiabaticEnergy(const Material& mat, double v1) {
  const int n = 4000;
  const double v0 = 1.0 / mat.rho0, h = (v1 - v0) / n;
  auto dedv = [&](double v, double e) { return -eosPressure(mat, 1.0 / v, e, 0.0); };
  double e = 0;
  for (int k = 0; k < n; ++k) {
    const double v = v0 + k * h;
    const double k1 = dedv(v, e), k2 = dedv(v + 0.5 * h, e + 0.5 * h * k1),
                 k3 = dedv(v + 0.5 * h, e + 0.5 * h * k2), k4 = dedv(v + h, e + h * k3);
    e += h / 6 * (k1 + 2 * k2 + 2 * k3 + k4);
  }
  return e;
}

/// Particles at the centres of an nx x ny x nz lattice of cubes of edge s from `origin`.
inline std::vector<Vec3> lattice(const Vec3& origin, int nx, int ny, int nz, double s) {
  std::vector<Vec3> p;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) p.push_back(origin + s * Vec3(i + 0.5, j + 0.5, k + 0.5));
  return p;
}

/// Mass of all nodes and particles, kg.
inline double totalMass(const Model& m) {
  double s = 0;
  for (double x : m.nodes.m) s += x;
  for (double x : m.particles.m) s += x;
  return s;
}

/// Linear momentum of all nodes and particles, kg m/s.
inline Vec3 totalMomentum(const Model& m) {
  Vec3 p = Vec3::Zero();
  for (std::size_t a = 0; a < m.nodes.size(); ++a) p += m.nodes.m[a] * m.nodes.v[a];
  for (std::size_t i = 0; i < m.particles.size(); ++i) p += m.particles.m[i] * m.particles.v[i];
  return p;
}

/// Arrival time of a wave front that takes a station from -v0 to rest: the first time the
/// station velocity `probe()` rises past -v0/2 (half of the jump), interpolated linearly
/// between the steps `advance()` takes; -1 if it has not arrived by t_end.
template <class Advance, class Probe>
double halfJumpArrival(Model& m, double v0, double t_end, Advance advance, Probe probe) {
  double t_prev = m.time, v_prev = -v0;
  while (m.time < t_end) {
    advance();
    const double v = probe();
    if (v > -0.5 * v0) return t_prev + (m.time - t_prev) * (-0.5 * v0 - v_prev) / (v - v_prev);
    t_prev = m.time;
    v_prev = v;
  }
  return -1.0;
}

/// One body: a structured box mesh of `mat` with uniform velocity.
inline Model boxModel(const Material& mat, const Vec3& size, int nx, int ny, int nz,
                      const Vec3& velocity = Vec3::Zero()) {
  Model model;
  model.materials.push_back(mat);
  addBody(model, "box", structuredBox(Vec3::Zero(), size, nx, ny, nz), 0, Placement{}, velocity,
          true);
  finaliseModel(model);
  return model;
}

}  // namespace fesph::testing
