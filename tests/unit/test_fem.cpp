// SPDX-License-Identifier: MIT
// Tet4 kinematics and the explicit FE solver: gradients, patch test, rigid rotation,
// conservation of momentum and energy.
#include "core/fem/element_forces.hpp"
#include "core/fem/tet4.hpp"
#include "core/solver/step.hpp"
#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

#include <random>

using namespace fesph;
using fesph::testing::boxModel;
using fesph::testing::elasticMaterial;

namespace {

std::array<Vec3, 4> randomTet(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (;;) {
    std::array<Vec3, 4> x;
    for (auto& p : x) p = Vec3(u(rng), u(rng), u(rng));
    if (tetVolume(x[0], x[1], x[2], x[3]) > 0.05) return x;
  }
}

bool interior(const Model& m, std::size_t a, const Vec3& size) {
  const Vec3& x = m.nodes.x0[a];
  const double tol = 1e-9;
  return (x.array() > tol).all() && ((size - x).array() > tol).all();
}

}  // namespace

TEST_CASE("tet4 shape gradients sum to zero and reproduce linear fields", "[unit][fem]") {
  // Reference: partition of unity and linear completeness of the P1 basis; round-off 1e-12.
  std::mt19937 rng(7);
  for (int trial = 0; trial < 100; ++trial) {
    const auto x = randomTet(rng);
    const TetGeometry g = tetGeometry(x[0], x[1], x[2], x[3]);
    Vec3 sum = Vec3::Zero();
    Mat3 completeness = Mat3::Zero();
    for (int a = 0; a < 4; ++a) {
      sum += g.grad[a];
      completeness += x[a] * g.grad[a].transpose();
    }
    REQUIRE(sum.norm() < 1e-12 * g.grad[0].norm());
    REQUIRE((completeness - Mat3::Identity()).norm() < 1e-12);
    REQUIRE(g.volume == Approx(tetVolume(x[0], x[1], x[2], x[3])).epsilon(1e-12));
  }
}

TEST_CASE("patch test: a linear velocity field gives uniform strain rate and no interior force",
          "[unit][fem]") {
  // Reference: constant-strain patch test. Every element sees the same rate of deformation,
  // the stress is uniform and interior nodes carry zero net force (1e-10 relative).
  const Vec3 size(2e-3, 3e-3, 4e-3);
  Model m = boxModel(elasticMaterial(), size, 4, 5, 6);
  Mat3 A;
  A << 10, 3, -2, 1, -5, 4, 2, 6, 8;  // 1/s, a general (non-symmetric) velocity gradient
  const double dt = 1e-4;  // strains of order 1e-3: well above round-off in J - 1
  for (std::size_t a = 0; a < m.nodes.size(); ++a) {
    m.nodes.v[a] = A * m.nodes.x0[a];
    m.nodes.x[a] = m.nodes.x0[a] + dt * m.nodes.v[a];  // x^n after one interval
  }
  m.controls.bulk_linear = m.controls.bulk_quadratic = 0;  // q would differ by element size
  computeElementForces(m, dt);

  const Sym s_ref = m.elems.state[0].s;
  const double p_ref = m.elems.state[0].p;
  REQUIRE(vonMises(s_ref) > 0);
  for (std::size_t e = 1; e < m.elems.size(); ++e) {
    REQUIRE((m.elems.state[e].s - s_ref).dot(m.elems.state[e].s - s_ref) <
            1e-20 * s_ref.dot(s_ref));
    REQUIRE(m.elems.state[e].p == Approx(p_ref).epsilon(1e-10));
  }
  double f_scale = 0;
  for (const auto& cf : m.corner_force) f_scale = std::max(f_scale, cf[0].norm());
  int n_interior = 0;
  for (std::size_t a = 0; a < m.nodes.size(); ++a) {
    if (!interior(m, a, size)) continue;
    ++n_interior;
    REQUIRE(m.nodes.f[a].norm() < 1e-10 * f_scale);
  }
  REQUIRE(n_interior == 3 * 4 * 5);
}

TEST_CASE("a rigid rotation gives zero strain rate", "[unit][fem]") {
  // Reference: objectivity of the rate of deformation; v = w x x has D = 0 (1e-12 of |w|).
  std::mt19937 rng(11);
  const Vec3 w(3.0, -7.0, 5.0);
  for (int trial = 0; trial < 50; ++trial) {
    const auto x = randomTet(rng);
    const TetGeometry g = tetGeometry(x[0], x[1], x[2], x[3]);
    std::array<Vec3, 4> v;
    for (int a = 0; a < 4; ++a) v[a] = w.cross(x[a]) + Vec3(1, 2, 3);
    const Mat3 L = velocityGradient(v, g.grad);
    const Mat3 D = 0.5 * (L + L.transpose());
    REQUIRE(D.norm() < 1e-12 * w.norm());
  }
}

TEST_CASE("a free body conserves linear momentum", "[unit][fem][conservation]") {
  // Reference: internal forces are equal and opposite (sum of corner forces of an element is
  // zero), so with no boundary conditions total momentum is constant: 1e-12 relative.
  Model m = boxModel(elasticMaterial(), Vec3(4e-3, 2e-3, 2e-3), 8, 4, 4);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-50.0, 50.0);
  double scale = 0;
  for (std::size_t a = 0; a < m.nodes.size(); ++a) {
    m.nodes.v[a] = Vec3(u(rng), u(rng), u(rng)) + Vec3(100, 0, 0);
    scale += m.nodes.m[a] * m.nodes.v[a].norm();
  }
  finaliseModel(m);
  const Vec3 p0 = m.energy.momentum;
  for (int i = 0; i < 300; ++i) step(m, 1.0);
  REQUIRE((m.energy.momentum - p0).norm() < 1e-12 * scale);
}

TEST_CASE("undamped elastic vibration conserves total energy", "[unit][fem][conservation]") {
  // Reference: central difference is symplectic; with no bulk viscosity the energy of a free
  // elastic vibration drifts only by round-off and O(dt^2) wobble. Issue criterion: < 0.5 %
  // over 2000 steps.
  Model m = boxModel(elasticMaterial(), Vec3(10e-3, 2e-3, 2e-3), 10, 2, 2);
  m.controls.bulk_linear = m.controls.bulk_quadratic = 0;
  for (std::size_t a = 0; a < m.nodes.size(); ++a) {
    const Vec3& x = m.nodes.x0[a];
    // a bending-like velocity field: transverse velocity growing along the bar
    m.nodes.v[a] = Vec3(0, 0, 20.0 * (x.x() / 10e-3 - 0.5) * (x.x() / 10e-3 - 0.5));
  }
  finaliseModel(m);
  double max_err = 0, max_internal = 0;
  for (int i = 0; i < 2000; ++i) {
    step(m, 1.0);
    max_err = std::max(max_err, m.energy.balanceError());
    max_internal = std::max(max_internal, m.energy.internal);
  }
  INFO("max internal " << max_internal << " J, initial " << m.energy.initial << " J");
  REQUIRE(max_internal > 0.05 * m.energy.initial);  // energy really moves between the terms
  REQUIRE(max_err < 0.005);
}

TEST_CASE("an element's stable step is l / (Q + sqrt(Q^2 + c^2)), Q from the bulk viscosity",
          "[unit][fem]") {
  // Reference: the tet's critical step with bulk viscosity (Flanagan & Belytschko 1981; the
  // LS-DYNA theory manual's element time step): l the smallest altitude, c the longitudinal
  // wave speed sqrt((K + 4G/3) / rho) of the linear EOS, Q = C1 c + C2 l |tr D| in compression
  // and 0 otherwise (then l / c). Each element's own formula, to round-off (1e-14).
  const Material mat = elasticMaterial();
  const double dt = 1e-7;
  for (const double rate : {0.0, 2e4, -2e4}) {  // 1/s per axis: rest, expansion, compression
    CAPTURE(rate);
    Model m = boxModel(mat, Vec3(2e-3, 3e-3, 4e-3), 2, 3, 4);
    for (std::size_t a = 0; a < m.nodes.size(); ++a) {
      m.nodes.v[a] = rate * m.nodes.x0[a];
      m.nodes.x[a] = m.nodes.x0[a] + dt * m.nodes.v[a];
    }
    computeElementForces(m, dt);
    for (std::size_t e = 0; e < m.elems.size(); ++e) {
      const auto& c = m.elems.conn[e];
      const Vec3 &x0 = m.nodes.x[c[0]], &x1 = m.nodes.x[c[1]], &x2 = m.nodes.x[c[2]],
                 &x3 = m.nodes.x[c[3]];
      const double area = 0.5 * std::max(std::max((x2 - x1).cross(x3 - x1).norm(),
                                                  (x2 - x0).cross(x3 - x0).norm()),
                                         std::max((x1 - x0).cross(x3 - x0).norm(),
                                                  (x1 - x0).cross(x2 - x0).norm()));
      const double len = 3 * tetVolume(x0, x1, x2, x3) / area;  // the smallest altitude
      const double rho = mat.rho0 * m.elems.V0[e] / m.elems.V[e];
      const double c_wave = std::sqrt((mat.K + 4.0 * mat.G / 3.0) / rho);
      // the rate at the midpoint configuration x0 + (dt/2) v, where the gradient of v = rate x0
      // is rate / (1 + rate dt/2) per axis
      const double trD = 3 * rate / (1 + 0.5 * rate * dt);
      const double Q = trD < 0 ? m.controls.bulk_linear * c_wave +
                                     m.controls.bulk_quadratic * len * -trD
                               : 0.0;
      const double expected = len / (Q + std::sqrt(Q * Q + c_wave * c_wave));
      REQUIRE(m.elems.dt[e] == Approx(expected).epsilon(1e-14));
      if (rate < 0) REQUIRE(m.elems.dt[e] < 0.99 * len / c_wave);  // the viscosity shortens it
    }
  }
}
