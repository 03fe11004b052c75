// SPDX-License-Identifier: MIT
// Kinematic contact between element bodies in motion: two elastic bars meeting end to end
// (elementary bar theory), a block landing obliquely with and without friction (Coulomb),
// a projectile stopped by the faces exposed by erosion, and thread-count independence.
#include "core/contact/node_face_contact.hpp"
#include "core/contact/surfaces.hpp"
#include "core/fem/element_forces.hpp"
#include "core/solver/boundary.hpp"
#include "core/solver/step.hpp"
#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

#ifdef _OPENMP
#include <omp.h>
#endif

using namespace fesph;

namespace {

// One solver step with these contact controls.
void stepWithContact(Model& m, double t_stop, const ContactControls& contact) {
  m.controls.contact = contact;
  step(m, t_stop);
}

Vec3 bodyMomentum(const Model& m, int b) {
  Vec3 p = Vec3::Zero();
  for (std::size_t a = m.bodies[b].node_begin; a < m.bodies[b].node_end; ++a)
    p += m.nodes.m[a] * m.nodes.v[a];
  return p;
}

/// Two bodies, each a structured box: `a` at the origin, `b` translated.
Model twoBoxes(const Vec3& size_a, const std::array<int, 3>& cells_a, const Vec3& v_a,
               const Vec3& size_b, const std::array<int, 3>& cells_b, const Vec3& origin_b,
               const Vec3& v_b, double nu = 0.3) {
  Model m;
  m.materials.push_back(fesph::testing::elasticMaterial(7850, 200e9, nu));
  addBody(m, "a", structuredBox(Vec3::Zero(), size_a, cells_a[0], cells_a[1], cells_a[2]), 0,
          Placement{}, v_a, true);
  Placement p;
  p.translation = origin_b;
  addBody(m, "b", structuredBox(Vec3::Zero(), size_b, cells_b[0], cells_b[1], cells_b[2]), 0, p,
          v_b, false);
  finaliseModel(m);
  buildSurfaces(m);
  return m;
}

// Largest depth of a node of body `b` inside a live element of another body, as the smallest
// barycentric coordinate (0: on a face, 0.25: at the centroid; <= 0: not inside).
double deepestInside(const Model& m, int b) {
  double deepest = -1;
  for (std::size_t a = m.bodies[b].node_begin; a < m.bodies[b].node_end; ++a) {
    if (!(m.nodes.m[a] > 0)) continue;
    for (std::size_t e = 0; e < m.elems.size(); ++e) {
      if (m.elems.body[e] == b || m.elems.status[e] != ElemStatus::Live) continue;
      const auto& c = m.elems.conn[e];
      const Vec3 &x0 = m.nodes.x[c[0]], &x1 = m.nodes.x[c[1]], &x2 = m.nodes.x[c[2]],
                 &x3 = m.nodes.x[c[3]], &p = m.nodes.x[a];
      const double V = tetVolume(x0, x1, x2, x3);
      const double l[4] = {tetVolume(p, x1, x2, x3) / V, tetVolume(x0, p, x2, x3) / V,
                           tetVolume(x0, x1, p, x3) / V, tetVolume(x0, x1, x2, p) / V};
      deepest = std::max(deepest, std::min({l[0], l[1], l[2], l[3]}));
    }
  }
  return deepest;
}

}  // namespace

TEST_CASE("two elastic bars meeting end to end exchange their velocities",
          "[verification][contact]") {
  // Reference: elementary bar theory for equal bars at +-v0: contact lasts 2L/c, c =
  // sqrt(E/rho), the bars leave with each other's velocity; by symmetry the same as one bar
  // on a frictionless rigid wall. Poisson's ratio 0 makes the 3-D bar the 1-D bar of the
  // theory (with nu = 0.3, 40 cells, lateral inertia kept 3.6 % of the momentum in ringing).
  // Tolerances: duration 5%; velocities 2% of v0, and the contact must match the rigid-wall
  // twin to 0.1%; total momentum 1e-12 of one bar's; penetration 1% of the element size;
  // energy budget closes to 1%.
  const double L = 40e-3, w = 2e-3, h = 0.5e-3, v0 = 10.0, nu = 0.0;
  Model m = twoBoxes(Vec3(L, w, w), {80, 2, 2}, Vec3(v0, 0, 0), Vec3(L, w, w), {80, 2, 2},
                     Vec3(L, 0, 0), Vec3(-v0, 0, 0), nu);
  // Elastic theory: no bulk viscosity (it dissipates in the wave front and slows the rebound).
  m.controls.bulk_linear = m.controls.bulk_quadratic = 0;
  const double c = std::sqrt(200e9 / 7850.0);
  const double p_bar = bodyMomentum(m, 0).norm();
  // end nodes of bar a and the coincident ones of bar b
  std::vector<std::pair<std::size_t, std::size_t>> pairs;
  for (std::size_t a = m.bodies[0].node_begin; a < m.bodies[0].node_end; ++a)
    for (std::size_t b = m.bodies[1].node_begin; b < m.bodies[1].node_end; ++b)
      if ((m.nodes.x0[a] - m.nodes.x0[b]).norm() < 1e-9) pairs.emplace_back(a, b);
  REQUIRE(pairs.size() == 9);

  double t_first = -1, t_last = -1, max_pen = 0, max_dp = 0;
  const double t_end = 1.6 * 2 * L / c;
  while (m.time < t_end) {
    const Vec3 p_before = bodyMomentum(m, 0);
    const double t0 = m.time;
    stepWithContact(m, t_end, ContactControls{});
    // only contact changes a bar's momentum
    if ((bodyMomentum(m, 0) - p_before).norm() > 1e-6 * p_bar) {
      if (t_first < 0) t_first = t0;
      t_last = m.time;
    }
    Vec3 p_total = Vec3::Zero();
    for (std::size_t a = 0; a < m.nodes.size(); ++a) p_total += m.nodes.m[a] * m.nodes.v[a];
    max_dp = std::max(max_dp, p_total.norm() / p_bar);
    for (const auto& [a, b] : pairs)
      max_pen = std::max(max_pen, m.nodes.x[a].x() - m.nodes.x[b].x());
  }
  const double va = bodyMeanVelocity(m, 0).x(), vb = bodyMeanVelocity(m, 1).x();
  const double duration = t_last - t_first;
  double kinetic = 0;
  for (std::size_t a = 0; a < m.nodes.size(); ++a)
    kinetic += 0.5 * m.nodes.m[a] * m.nodes.v[a].squaredNorm();
  const double balance =
      (kinetic + m.energy.internal + m.energy.contact) / m.energy.initial - 1;

  // the twin: one bar on a rigid wall at its far end
  Model wall = fesph::testing::boxModel(fesph::testing::elasticMaterial(7850, 200e9, nu),
                                        Vec3(L, w, w), 80, 2, 2, Vec3(v0, 0, 0));
  wall.controls.bulk_linear = wall.controls.bulk_quadratic = 0;
  RigidWall rw;
  rw.point = Vec3(L, 0, 0);
  rw.normal = -Vec3::UnitX();
  wall.walls.push_back(rw);
  while (wall.time < t_end) step(wall, t_end);
  const double v_wall = bodyMeanVelocity(wall, 0).x();

  INFO("velocities after: " << va << ", " << vb << " m/s (rigid wall twin " << v_wall
                            << "); contact " << duration * 1e6 << " us vs 2L/c "
                            << 2 * L / c * 1e6 << " us; momentum drift " << max_dp
                            << "; penetration " << max_pen * 1e6 << " um; energy balance "
                            << balance << ", contact work " << m.energy.contact
                            << " J of " << m.energy.initial << " J");
  CHECK(std::abs(va + v0) < 0.02 * v0);
  CHECK(std::abs(vb - v0) < 0.02 * v0);
  CHECK(std::abs(va - v_wall) < 1e-3 * v0);
  CHECK(std::abs(duration - 2 * L / c) < 0.05 * 2 * L / c);
  CHECK(max_dp < 1e-12);
  CHECK(max_pen < 0.01 * h);
  CHECK(std::abs(balance) < 0.01);
}

TEST_CASE("a block landing obliquely keeps or loses its sliding as friction says",
          "[verification][contact]") {
  // Reference: Coulomb. A 4 mm steel cube at (10, 0, -10) m/s lands on a free 12x12x2 mm
  // plate. Frictionless: its tangential velocity stays within 1% (only the slight tilt of
  // the deforming faces acts sideways). mu = 0.2: it loses sliding speed, at most mu times
  // the normal velocity change (+5% for tilted faces), at least half of that (it slides
  // throughout), and never goes backwards.
  auto run = [](double mu, double& vx_min) {
    Model m = twoBoxes(Vec3(4e-3, 4e-3, 4e-3), {4, 4, 4}, Vec3(10, 0, -10),
                       Vec3(12e-3, 12e-3, 2e-3), {12, 12, 2}, Vec3(-4.5e-3, -4.5e-3, -2.05e-3),
                       Vec3::Zero());
    ContactControls cc;
    cc.friction = mu;
    vx_min = 10;
    const double t_end = 15e-6;
    while (m.time < t_end) {
      stepWithContact(m, t_end, cc);
      vx_min = std::min(vx_min, bodyMeanVelocity(m, 0).x());
    }
    REQUIRE(deepestInside(m, 0) < 1e-3);
    REQUIRE(deepestInside(m, 1) < 1e-3);
    return bodyMeanVelocity(m, 0);
  };
  double vx_min = 0;
  const Vec3 v_free = run(0.0, vx_min);
  INFO("frictionless: block leaves at " << v_free.transpose() << " m/s");
  REQUIRE(v_free.z() > 0);  // it did land and bounce
  CHECK(std::abs(v_free.x() - 10.0) < 0.01 * 10.0);
  const Vec3 v_mu = run(0.2, vx_min);
  const double dvn = v_mu.z() + 10.0, dvt = 10.0 - v_mu.x();
  INFO("mu = 0.2: block leaves at " << v_mu.transpose() << " m/s; lowest sliding speed "
                                    << vx_min << " m/s; dvt/dvn " << dvt / dvn);
  CHECK(dvt <= 0.2 * dvn * 1.05);
  CHECK(dvt >= 0.5 * 0.2 * dvn);
  CHECK(vx_min > 0);
}

TEST_CASE("faces exposed by erosion stop a projectile", "[verification][contact]") {
  // Reference: impenetrability. A 6x6x3 mm plate loses the elements of a 2x2 mm crater two
  // layers deep; a 1.6 mm block starting inside the crater 0.1 mm above its floor drops onto
  // it at 50 m/s. With the surfaces updated, no node of either body ever enters a live
  // element of the other (point-in-tet, barycentric depth below 1e-3); with the surfaces
  // left as they were before the erosion (the control), the block sinks into the floor.
  auto run = [](bool update_surfaces) {
    Model m = twoBoxes(Vec3(1.6e-3, 1.6e-3, 1e-3), {2, 2, 1}, Vec3(0, 0, -50),
                       Vec3(6e-3, 6e-3, 3e-3), {6, 6, 3}, Vec3(-2.2e-3, -2.2e-3, -1.1e-3),
                       Vec3::Zero());
    // plate cells (i, j, k) with i, j in {2, 3} and k in {1, 2}: 6 tets each, cell by cell
    const std::size_t e0 = m.bodies[1].elem_begin;
    for (int k = 1; k <= 2; ++k)
      for (int j = 2; j <= 3; ++j)
        for (int i = 2; i <= 3; ++i)
          for (int t = 0; t < 6; ++t) {
            const std::size_t e = e0 + 6 * ((k * 6 + j) * 6 + i) + t;
            m.elems.status[e] = ElemStatus::Eroded;
            if (update_surfaces) removeElementFromSurfaces(m, e);
          }
    // nodes left without a live element are inactive
    std::vector<int> live(m.nodes.size(), 0);
    for (std::size_t e = 0; e < m.elems.size(); ++e)
      if (m.elems.status[e] == ElemStatus::Live)
        for (int a : m.elems.conn[e]) live[a] = 1;
    for (std::size_t a = 0; a < m.nodes.size(); ++a)
      if (!live[a]) m.nodes.m[a] = 0, m.nodes.v[a] = Vec3::Zero();
    double deepest = -1;
    const double t_end = 5e-6;
    while (m.time < t_end) {
      stepWithContact(m, t_end, ContactControls{});
      deepest = std::max({deepest, deepestInside(m, 0), deepestInside(m, 1)});
    }
    return std::make_pair(deepest, bodyMeanVelocity(m, 0).z());
  };
  const auto [deepest, vz] = run(true);
  INFO("updated surfaces: deepest node " << deepest << ", block vz " << vz << " m/s");
  CHECK(deepest < 1e-3);
  CHECK(vz > -25.0);  // it was stopped (bounced or resting)
  const auto [deepest_stale, vz_stale] = run(false);
  INFO("stale surfaces: deepest node " << deepest_stale << ", block vz " << vz_stale);
  CHECK(deepest_stale > 0.05);
}

TEST_CASE("contact corrections are the same for any thread count", "[verification][contact]") {
  // Reference: bit-for-bit equality of all velocities and the booked work after the contact
  // phase, from the same state, with 1, 2 and 3 threads.
#ifdef _OPENMP
  Model m = twoBoxes(Vec3(4e-3, 4e-3, 4e-3), {4, 4, 4}, Vec3(10, 0, -10),
                     Vec3(12e-3, 12e-3, 2e-3), {12, 12, 2}, Vec3(-4.5e-3, -4.5e-3, -2.05e-3),
                     Vec3::Zero());
  ContactControls cc;
  cc.friction = 0.3;
  while (m.time < 6e-6) stepWithContact(m, 6e-6, cc);  // in contact by now
  computeElementForces(m, m.dt);
  const double dt = stableTimeStep(m, 1.0);
  integrateVelocities(m, 0.5 * (m.dt + dt));
  const int default_threads = omp_get_max_threads();
  std::vector<Model> results;
  for (int threads : {1, 2, 3}) {
    omp_set_num_threads(threads);
    results.push_back(m);
    enforceNodeFaceContact(results.back(), dt, cc);
  }
  omp_set_num_threads(default_threads);
  REQUIRE(results[0].nodes.v != m.nodes.v);  // contact did act
  for (const Model& r : results) {
    REQUIRE(r.nodes.v == results[0].nodes.v);
    REQUIRE(r.energy.contact == results[0].energy.contact);
  }
#endif
}
