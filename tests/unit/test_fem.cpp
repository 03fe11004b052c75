// SPDX-License-Identifier: MIT
// Tet4 kinematics and the explicit FE solver: gradients, patch test, rigid rotation,
// conservation of momentum and energy.
#include "core/common/error.hpp"
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

TEST_CASE("average nodal pressure: each element's pressure and wave speed blend its nodes' and "
          "its own volume", "[unit][fem]") {
  // Reference: Bonet & Burton (1998) average nodal pressure, as blended here (docs/design.md):
  // each node's volume ratio J_a = sum V_e / sum V0_e over its live elements, the element's
  // density rho0 / mean(J_a) over its four nodes; pressure and squared wave speed are
  // (1 - f) times their values at that density plus f times those at the element's own
  // density, f = anp_element_fraction. With ANP off, the element's own density alone. Linear
  // EOS (p = K (rho/rho0 - 1)), a mesh distorted by up to 2 % of its spacing, at rest: to
  // round-off (1e-12 K in the pressure, 1e-14 in the step).
  const Material mat = elasticMaterial();
  for (const bool anp : {true, false}) {
    CAPTURE(anp);
    Model m = boxModel(mat, Vec3(3e-3, 3e-3, 3e-3), 3, 3, 3);
    m.controls.average_nodal_pressure = anp;
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-2e-5, 2e-5);  // m, 2 % of 1 mm
    for (Vec3& x : m.nodes.x) x += Vec3(jitter(rng), jitter(rng), jitter(rng));
    computeElementForces(m, 1e-8);

    const Elements& el = m.elems;
    std::vector<double> vol(m.nodes.size(), 0.0), vol0(m.nodes.size(), 0.0);
    for (std::size_t e = 0; e < el.size(); ++e)
      for (int a : el.conn[e]) {
        const auto& c = el.conn[e];
        vol[a] += tetVolume(m.nodes.x[c[0]], m.nodes.x[c[1]], m.nodes.x[c[2]], m.nodes.x[c[3]]);
        vol0[a] += el.V0[e];
      }
    const double f = anp ? m.controls.anp_element_fraction : 1.0;
    const double M = mat.K + 4.0 * mat.G / 3.0;
    double spread = 0;  // how far the own pressures stray from the averaged ones
    for (std::size_t e = 0; e < el.size(); ++e) {
      const auto& c = el.conn[e];
      const double V = tetVolume(m.nodes.x[c[0]], m.nodes.x[c[1]], m.nodes.x[c[2]],
                                 m.nodes.x[c[3]]);
      double J = 0;
      for (int a : c) J += 0.25 * vol[a] / vol0[a];
      const double rho_avg = mat.rho0 / J, rho_own = mat.rho0 * el.V0[e] / V;
      const double p_avg = mat.K * (rho_avg / mat.rho0 - 1);
      const double p_own = mat.K * (rho_own / mat.rho0 - 1);
      spread = std::max(spread, std::abs(p_own - p_avg));
      REQUIRE(el.state[e].p == Approx((1 - f) * p_avg + f * p_own).margin(1e-12 * mat.K));
      const double c_wave = std::sqrt((1 - f) * M / rho_avg + f * M / rho_own);
      REQUIRE(el.dt[e] == Approx(el.len[e] / c_wave).epsilon(1e-14));
    }
    std::printf("[fem] ANP %s: own and averaged pressures differ by up to %.3g Pa\n",
                anp ? "on" : "off", spread);
    REQUIRE(spread > 1e-4 * mat.K);  // the blend is seen: the two densities differ
  }
}

TEST_CASE("an element's energy follows de = -p dv to second order in its step (Mie-Grueneisen)",
          "[unit][fem][conservation]") {
  // Reference: the energy equation of a compressed point without dissipation, de = -p(rho, e) dv
  // (v = 1/rho), integrated here with RK4 in v (4000 steps, converged far below the checks).
  // The element's update is trapezoidal in p with one predictor and one corrector, since the
  // Mie-Grueneisen p depends on the e it updates: second order, so its error at 10 %
  // compression falls ~4x when the step halves (checked: > 3x), and the stored pressure is
  // the EOS at the stored energy (1e-12). Uniform compression of a cube (no deviatoric stress,
  // bulk viscosity off), Mie-Grueneisen steel (c0 4570 m/s, s 1.49, Gamma0 1.93).
  const Material mat = fesph::testing::mieGruneisenSteel();
  const double strain = 1.0 - std::cbrt(0.9);  // per axis, to V/V0 = 0.9
  auto compress = [&](int steps, double& v_end) {
    Model m = boxModel(mat, Vec3(1e-3, 1e-3, 1e-3), 1, 1, 1);
    m.controls.bulk_linear = m.controls.bulk_quadratic = 0;
    const double dt = 1e-6 / steps;
    for (std::size_t a = 0; a < m.nodes.size(); ++a)
      m.nodes.v[a] = -(strain / 1e-6) * m.nodes.x0[a];
    for (int n = 1; n <= steps; ++n) {
      for (std::size_t a = 0; a < m.nodes.size(); ++a)
        m.nodes.x[a] = m.nodes.x0[a] + (n * dt) * m.nodes.v[a];
      computeElementForces(m, dt);
    }
    const PointState& st = m.elems.state[0];
    v_end = 1.0 / m.elems.rho[0];
    REQUIRE(st.p == Approx(eosPressure(mat, m.elems.rho[0], st.e, 0.0)).epsilon(1e-12));
    return st.e;
  };
  double v1 = 0;
  const double e10 = compress(10, v1), e20 = compress(20, v1), e40 = compress(40, v1);
  // the same end volume for every step count
  const double e = fesph::testing::adiabaticEnergy(mat, v1);
  const double err10 = std::abs(e10 - e), err20 = std::abs(e20 - e), err40 = std::abs(e40 - e);
  std::printf("[fem] energy of a compressed cube, %.6g J/kg: errors %.3g / %.3g / %.3g J/kg at "
              "10 / 20 / 40 steps (ratios %.2f, %.2f)\n",
              e, err10, err20, err40, err10 / err20, err20 / err40);
  CHECK(err40 < 1e-4 * e);
  CHECK(err10 / err20 > 3);
  CHECK(err20 / err40 > 3);
}

TEST_CASE("an element's plastic work is sigma_y d(eps_p) V on its midpoint configuration",
          "[unit][fem][conservation]") {
  // Reference: uniaxial strain worked by hand (uniaxialPlasticWork, tests/support/models.hpp).
  // A 1 mm cube of six tets, elastic-perfectly plastic and on its yield surface, compressed
  // along z by prescribed motion z = z0 (1 - r t) to 90 % of its volume (bulk viscosity off).
  // The rate and the volume the work is booked on are both the midpoint configuration's, so
  // each step's A (2/3) r / (1 - r t) dt V0 (1 - r t) is the exact plastic power times dt:
  // the work is exact to round-off (1e-12) at any step; on the end volume it would be 0.5 %
  // off at 10 steps.
  const Material mat = fesph::testing::perfectlyPlasticMaterial();
  const double t_end = 1e-6, r = 0.1 / t_end;
  const double exact = fesph::testing::uniaxialPlasticWork(mat, r, 1e-9, t_end);
  for (const int steps : {7, 10}) {
    Model m = boxModel(mat, Vec3(1e-3, 1e-3, 1e-3), 1, 1, 1);
    m.controls.bulk_linear = m.controls.bulk_quadratic = 0;
    const double dt = t_end / steps;
    for (std::size_t a = 0; a < m.nodes.size(); ++a)
      m.nodes.v[a] = Vec3(0, 0, -r * m.nodes.x0[a].z());
    for (PointState& st : m.elems.state) st.s = fesph::testing::yieldedInUniaxialCompression(mat);
    for (int n = 1; n <= steps; ++n) {
      for (std::size_t a = 0; a < m.nodes.size(); ++a)
        m.nodes.x[a] = m.nodes.x0[a] + (n * dt) * m.nodes.v[a];
      computeElementForces(m, dt);
    }
    INFO(steps << " steps: " << m.energy.plastic_work << " J, by hand " << exact << " J");
    CHECK(m.energy.plastic_work == Approx(exact).epsilon(1e-12));
  }
}

TEST_CASE("an element's altitude at its first force pass is kept as its reference length",
          "[unit][fem]") {
  // Reference: the safety trigger (triggers.cpp) compares an element's smallest altitude with
  // the one it had at the first step (len0); with len0 never set it would never fire. The
  // first pass records it, later passes leave it, whatever the element's length becomes.
  Model m = boxModel(elasticMaterial(), Vec3(2e-3, 2e-3, 2e-3), 2, 2, 2);
  for (std::size_t e = 0; e < m.elems.size(); ++e) REQUIRE(m.elems.len0[e] == 0.0);
  computeElementForces(m, 1e-8);
  const std::vector<double> first = m.elems.len;
  for (std::size_t e = 0; e < m.elems.size(); ++e) {
    REQUIRE(first[e] > 0.0);
    REQUIRE(m.elems.len0[e] == first[e]);
  }
  for (Vec3& x : m.nodes.x) x.z() *= 0.5;  // squashed to half its height
  computeElementForces(m, 1e-8);
  for (std::size_t e = 0; e < m.elems.size(); ++e) {
    REQUIRE(m.elems.len[e] < 0.9 * first[e]);
    REQUIRE(m.elems.len0[e] == first[e]);
  }
}

TEST_CASE("pass A four elements at a time: each element gets the scalar functions' bits",
          "[unit][fem]") {
  // Reference: pass A takes four elements through one instruction stream (element_forces.cpp,
  // passALanes), each lane with the operations of tetGeometry, tetVolume, velocityGradient,
  // Sym::fromMatrix and the trial of updateDeviatoricStress in their order. So an element's
  // volume, density, divergence and stress history after the pass must equal, bit for bit,
  // what those scalar functions give it one element at a time. Mixed on purpose: two
  // materials (one hardening, rate-dependent, heating, with damage), elements that yield and
  // that do not, failed ones (damage 1), a converted one inside a group of four, and an
  // element count that is not a multiple of four (the last group repeats its last element).
  Material copper = fesph::testing::perfectlyPlasticMaterial();  // OFHC, Johnson & Cook 1983/85
  copper.A = 90e6, copper.B = 292e6, copper.n = 0.31, copper.C = 0.025, copper.m = 1.09;
  copper.T_melt = 1356, copper.cp = 383, copper.damage = true;
  copper.D1 = 0.54, copper.D2 = 4.89, copper.D3 = -3.03, copper.D4 = 0.014, copper.D5 = 1.12;
  REQUIRE(finaliseMaterial(copper).empty());
  Model m =
      boxModel(fesph::testing::perfectlyPlasticMaterial(), Vec3(1.5e-3, 1.5e-3, 5e-4), 3, 3, 1);
  m.materials.push_back(copper);
  const std::size_t ne = m.elems.size();
  REQUIRE(ne % 4 != 0);
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (std::size_t a = 0; a < m.nodes.size(); ++a) {
    m.nodes.x[a] = m.nodes.x0[a] + 1e-5 * Vec3(u(rng), u(rng), u(rng));
    m.nodes.v[a] = 300.0 * Vec3(u(rng), u(rng), u(rng));
  }
  for (std::size_t e = 0; e < ne; ++e) {
    m.elems.material[e] = (e % 3 == 0) ? 1 : 0;
    PointState& st = m.elems.state[e];
    st.s = Sym{u(rng), u(rng), 0, u(rng), u(rng), u(rng)} * 2e8;
    st.s.zz = -(st.s.xx + st.s.yy);
    st.eps_p = 0.3 * (1 + u(rng));
    st.eps_rate = 1e4 * (1 + u(rng));
    st.T = 400 + 100 * u(rng);
    st.damage = (e % 7 == 3) ? 1.0 : 0.4 * (1 + u(rng));
  }
  m.elems.status[5] = ElemStatus::Converted;
  const Model before = m;
  const double dt = 2e-9;
  computeElementForces(m, dt);

  int yielded = 0, elastic = 0;
  for (std::size_t e = 0; e < ne; ++e) {
    const Elements& el = before.elems;
    if (el.status[e] != ElemStatus::Live) {
      CHECK(m.elems.V[e] == el.V[e]);
      continue;
    }
    const auto& c = el.conn[e];
    std::array<Vec3, 4> x, v, mid;
    for (int a = 0; a < 4; ++a) {
      x[a] = before.nodes.x[c[a]];
      v[a] = before.nodes.v[c[a]];
      mid[a] = x[a] - 0.5 * dt * v[a];
    }
    const TetGeometry g = tetGeometry(mid[0], mid[1], mid[2], mid[3]);
    const double vol = tetVolume(x[0], x[1], x[2], x[3]);
    const Mat3 L = velocityGradient(v, g.grad);
    const Material& mat = before.materials[el.material[e]];
    PointState st = el.state[e];
    const double eps_p0 = st.eps_p;
    updateDeviatoricStress(mat, Sym::fromMatrix(L), 0.5 * (L - L.transpose()), dt, el.rho[e], st);
    (st.eps_p > eps_p0 ? yielded : elastic) += 1;
    const PointState& got = m.elems.state[e];
    INFO("element " << e);
    CHECK(m.elems.V[e] == vol);
    CHECK(m.elems.rho[e] == mat.rho0 * el.V0[e] / vol);
    CHECK(m.elems.div_v[e] == Sym::fromMatrix(L).trace());
    CHECK(got.s.xx == st.s.xx);
    CHECK(got.s.yy == st.s.yy);
    CHECK(got.s.zz == st.s.zz);
    CHECK(got.s.xy == st.s.xy);
    CHECK(got.s.yz == st.s.yz);
    CHECK(got.s.zx == st.s.zx);
    CHECK(got.eps_p == st.eps_p);
    CHECK(got.T == st.T);
    CHECK(got.damage == st.damage);
  }
  CHECK(yielded > 10);
  CHECK(elastic > 10);
}

TEST_CASE("pass C four elements at a time: each element gets the one-at-a-time bits",
          "[unit][fem]") {
  // Reference: pass C takes a group of four elements of one material through one instruction
  // stream (passCLanes), each lane with the operations of volumetricResponseAndForces, the
  // function that groups spanning two materials still call one element at a time. The same
  // model with its material given twice (identical copies), alternately to every other
  // element, takes that function for every element; each element's length, bulk viscosity,
  // stable step, energy, pressure and corner forces, and the energy sums, must be the same
  // bits both ways. Mixed on purpose: linear and Mie-Grueneisen EOS, with and without ANP,
  // elements compressed and expanded, in compression and in expansion (viscosity or not),
  // failed ones (their tension cut), a converted one, a count not divisible by four.
  Material steel = fesph::testing::mieGruneisenSteel();
  steel.strength = StrengthModel::JohnsonCook;
  steel.A = 800e6;
  REQUIRE(finaliseMaterial(steel).empty());
  for (const Material& mat : {fesph::testing::perfectlyPlasticMaterial(), steel}) {
    for (const bool anp : {false, true}) {
      Model lanes = boxModel(mat, Vec3(1.5e-3, 1.5e-3, 5e-4), 3, 3, 1);
      lanes.controls.average_nodal_pressure = anp;
      const std::size_t ne = lanes.elems.size();
      REQUIRE(ne % 4 != 0);
      std::mt19937 rng(9);
      std::uniform_real_distribution<double> u(-1.0, 1.0);
      for (std::size_t a = 0; a < lanes.nodes.size(); ++a) {
        lanes.nodes.x[a] = lanes.nodes.x0[a] * (1 + 0.03 * u(rng));
        lanes.nodes.v[a] = 300.0 * Vec3(u(rng), u(rng), u(rng));
      }
      for (std::size_t e = 0; e < ne; ++e) {
        PointState& st = lanes.elems.state[e];
        st.s = Sym{u(rng), u(rng), 0, u(rng), u(rng), u(rng)} * 2e8;
        st.p = 1e9 * u(rng);
        st.e = 3e4 * u(rng);
        st.damage = (e % 7 == 3) ? 1.0 : 0.0;
      }
      lanes.elems.status[6] = ElemStatus::Converted;
      Model single = lanes;
      single.materials.push_back(single.materials[0]);
      for (std::size_t e = 1; e < ne; e += 2) single.elems.material[e] = 1;
      // two passes, the nodes moved in between: the second keeps the first's reference length
      const double dt = 2e-9;
      for (Model* model : {&lanes, &single}) {
        computeElementForces(*model, dt);
        for (std::size_t a = 0; a < model->nodes.size(); ++a)
          model->nodes.x[a] += 20 * dt * model->nodes.v[a];
        computeElementForces(*model, dt);
      }

      INFO((mat.eos == EosModel::Linear ? "linear EOS" : "Mie-Grueneisen") << ", ANP " << anp);
      int compressed = 0, expanded = 0, viscous = 0, failed_cut = 0;
      for (std::size_t e = 0; e < ne; ++e) {
        if (lanes.elems.status[e] != ElemStatus::Live) continue;
        INFO("element " << e);
        const Elements &a = lanes.elems, &b = single.elems;
        CHECK(a.len[e] == b.len[e]);
        CHECK(a.len0[e] == b.len0[e]);
        CHECK(a.len0[e] != a.len[e]);
        CHECK(a.q[e] == b.q[e]);
        CHECK(a.dt[e] == b.dt[e]);
        CHECK(a.state[e].e == b.state[e].e);
        CHECK(a.state[e].p == b.state[e].p);
        for (int k = 0; k < 4; ++k)
          for (int i = 0; i < 3; ++i)
            CHECK(lanes.corner_force[e][k][i] == single.corner_force[e][k][i]);
        (a.rho[e] > mat.rho0 ? compressed : expanded) += 1;
        viscous += a.q[e] > 0;
        failed_cut += a.state[e].damage >= 1.0 && a.state[e].p == 0.0;
      }
      CHECK(lanes.energy.internal == single.energy.internal);
      CHECK(lanes.energy.bulk_viscosity == single.energy.bulk_viscosity);
      for (std::size_t n = 0; n < lanes.nodes.size(); ++n)
        for (int i = 0; i < 3; ++i) CHECK(lanes.nodes.f[n][i] == single.nodes.f[n][i]);
      CHECK(compressed > 5);
      CHECK(expanded > 5);
      CHECK(viscous > 5);
      CHECK(failed_cut > 0);
    }
  }
}

TEST_CASE("the central difference stays second order when the step changes",
          "[unit][fem][conservation]") {
  // Reference: leapfrog with a varying step, v^{n+1/2} = v^{n-1/2} + (dt^{n-1/2} +
  // dt^{n+1/2})/2 a^n, x^{n+1} = x^n + dt^{n+1/2} v^{n+1/2} (Belytschko, Liu & Moran, Nonlinear
  // Finite Elements, 2000, sec. 6.2.1), is second order for any step sequence; taking the new
  // step alone for the velocity is first order wherever the step changes. A free elastic
  // vibration (the energy test's bar) run to 2 us, its step cut to 0.3 of itself every 20th
  // step (a scene's output times do this) and regrowing by at most 1.1x a step (back in 13
  // steps): its positions against a run at Courant factor 0.00625, at Courant factors 0.1 and
  // 0.05 (at the default 0.5 the order does not show yet). The error must fall by more than 3x
  // when the step halves (second order: ~4x; measured 4.2; first order: ~2x).
  const double t_end = 2e-6;
  auto run = [&](double courant, bool cut) {
    Model m = boxModel(elasticMaterial(), Vec3(10e-3, 2e-3, 2e-3), 10, 2, 2);
    m.controls.bulk_linear = m.controls.bulk_quadratic = 0;
    m.controls.courant = courant;
    for (std::size_t a = 0; a < m.nodes.size(); ++a) {
      const double s = m.nodes.x0[a].x() / 10e-3 - 0.5;
      m.nodes.v[a] = Vec3(0, 0, 20.0 * s * s);
    }
    finaliseModel(m);
    for (long n = 0; m.time < t_end; ++n)
      step(m, cut && n % 20 == 10 ? std::min(t_end, m.time + 0.3 * m.dt) : t_end);
    return m.nodes.x;
  };
  const std::vector<Vec3> reference = run(0.00625, false);
  auto error = [&](double courant) {
    const std::vector<Vec3> x = run(courant, true);
    double worst = 0;
    for (std::size_t a = 0; a < x.size(); ++a)
      worst = std::max(worst, (x[a] - reference[a]).norm());
    return worst;
  };
  const double e10 = error(0.1), e5 = error(0.05);
  std::printf("[fem] varying steps: position errors %.3g / %.3g m at Courant 0.1 / 0.05 "
              "(ratio %.2f)\n", e10, e5, e10 / e5);
  CHECK(e10 / e5 > 3);
}

TEST_CASE("the time step: Courant fraction, growth cap, landing on the end time, its limiter",
          "[unit][fem]") {
  // Reference: stableTimeStep's rules (docs/design.md, "Variable dt"), by hand on stable
  // steps set directly. dt = courant min(live elements', particles') steps, named after the
  // lowest index that attains the minimum, a particle only when strictly below every element;
  // at most dt_growth times the last step; the end time reached without a sliver: a remainder
  // under two steps is split in halves; a step under dt_min stops the run.
  Model m = boxModel(elasticMaterial(), Vec3(1e-3, 1e-3, 1e-3), 1, 1, 1);
  REQUIRE(m.elems.size() == 6);
  m.elems.dt = {3e-8, 2e-8, 5e-8, 2e-8, 4e-8, 6e-8};
  m.elems.status[2] = ElemStatus::Eroded;
  m.elems.dt[2] = 1e-12;  // an eroded element limits nothing
  const double courant = m.controls.courant, t_far = 1.0;
  CHECK(stableTimeStep(m, t_far) == courant * 2e-8);
  CHECK(m.dt_limiter == "element 1");

  appendParticle(m.particles, Vec3::Zero(), Vec3::Zero(), 1e-6, 1e-9, 1e-3, 1.3e-3, PointState{},
                 0, 0, -1);
  m.particles.dt[0] = 2e-8;  // a tie goes to the element
  CHECK(stableTimeStep(m, t_far) == courant * 2e-8);
  CHECK(m.dt_limiter == "element 1");
  m.particles.dt[0] = 1.5e-8;
  CHECK(stableTimeStep(m, t_far) == courant * 1.5e-8);
  CHECK(m.dt_limiter == "particle 0");
  m.particles.dt[0] = 1.0;

  m.dt = 0.5 * courant * 2e-8;  // the last step: the new one may grow by dt_growth at most
  CHECK(stableTimeStep(m, t_far) == m.controls.dt_growth * m.dt);
  CHECK(m.dt_limiter == "growth cap");
  m.dt = 0;

  const double dt = courant * 2e-8;
  m.time = 0.25;
  CHECK(stableTimeStep(m, m.time + 1.5 * dt) == Approx(0.75 * dt).epsilon(1e-6));
  CHECK(m.dt_limiter == "output/end time");
  CHECK(stableTimeStep(m, m.time + 0.5 * dt) == Approx(0.5 * dt).epsilon(1e-6));
  CHECK(m.dt_limiter == "output/end time");

  m.controls.dt_min = 2 * dt;
  CHECK_THROWS_AS(stableTimeStep(m, t_far), RunError);
}
