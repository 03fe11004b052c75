// SPDX-License-Identifier: MIT
// Pieces of a body and the residual velocity of its largest intact piece.
#include "core/analysis/fragments.hpp"
#include "core/contact/surfaces.hpp"
#include "core/conversion/erosion.hpp"
#include "core/sph/particle_body.hpp"
#include "core/state/model_build.hpp"
#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>

using namespace fesph;

TEST_CASE("a body cut in two by erosion has two pieces", "[unit][analysis]") {
  // Reference: exact mass bookkeeping. A 10-cell bar with its 4th cell layer eroded splits
  // into a 3-cell and a 6-cell piece; masses 3/10 and 6/10 of the bar (1e-12), and the
  // piece velocities are the (uniform) initial velocity.
  const Material steel = fesph::testing::elasticMaterial();
  Model m = fesph::testing::boxModel(steel, Vec3(10e-3, 1e-3, 1e-3), 10, 1, 1, Vec3(0, 0, -100));
  const double mass = steel.rho0 * 10e-9;
  for (std::size_t e = 0; e < m.elems.size(); ++e) {
    Vec3 c = Vec3::Zero();
    for (int a : m.elems.conn[e]) c += 0.25 * m.nodes.x0[a];
    if (c.x() > 3e-3 && c.x() < 4e-3) erodeElement(m, e, Trigger::PlasticStrain);
  }
  const std::vector<Piece> pieces = bodyPieces(m, 0);
  REQUIRE(pieces.size() == 2);
  REQUIRE(pieces[0].mass == Approx(0.6 * mass).epsilon(1e-12));
  REQUIRE(pieces[1].mass == Approx(0.3 * mass).epsilon(1e-12));
  REQUIRE((pieces[0].velocity - Vec3(0, 0, -100)).norm() < 1e-12);

  const ResidualVelocity r = residualVelocity(m, 0);
  REQUIRE(r.speed == Approx(100.0).epsilon(1e-12));
  REQUIRE(r.mass_fraction == Approx(0.6).epsilon(1e-12));
  REQUIRE(r.cleared);  // no other body
  // The fraction is of the body's mass at the start, rho0 V0: compressing the bar changes
  // its elements' volumes, not its mass.
  for (double& V : m.elems.V) V *= 0.8;
  REQUIRE(bodyInitialMass(m, 0) == Approx(mass).epsilon(1e-12));
  REQUIRE(residualVelocity(m, 0).mass_fraction == Approx(0.6).epsilon(1e-12));
}

TEST_CASE("a body of particles falls into pieces where its particles are no longer linked",
          "[unit][analysis]") {
  // Reference: debris.hpp's link, |x_i - x_j| <= 1.5 (r_i + r_j) with r = cbrt(V) / 2, and exact
  // mass bookkeeping. A row of five equal particles 1 mm apart (V = 1 mm^3: linked up to 1.5
  // mm) is one piece; moved 2 mm apart after the second, it is two, the larger (three
  // particles, moving at -200 m/s) first, with the mass fraction of the body's particles.
  Model m;
  m.materials.push_back(fesph::testing::elasticMaterial());
  m.bodies.push_back(Body{});
  m.bodies[0].name = "slug";
  m.bodies[0].is_projectile = true;
  m.bodies[0].discretisation = Discretisation::Sph;
  for (int k = 0; k < 5; ++k) {
    const Vec3 v = k < 2 ? Vec3(0, 0, -100) : Vec3(0, 0, -200);
    appendParticle(m.particles, Vec3(0, 0, 1e-3 * k), v, 2e-6, 1e-9, 1e-3, 1.3e-3, PointState{},
                   0, 0, -1);
  }
  REQUIRE(bodyInitialMass(m, 0) == Approx(10e-6).epsilon(1e-12));
  REQUIRE(bodyPieces(m, 0).size() == 1);
  for (int k = 2; k < 5; ++k) m.particles.x[k].z() += 1e-3;  // a 2 mm gap after the second
  const std::vector<Piece> pieces = bodyPieces(m, 0);
  REQUIRE(pieces.size() == 2);
  CHECK(pieces[0].particles == std::vector<int>{2, 3, 4});
  CHECK(pieces[1].particles == std::vector<int>{0, 1});
  CHECK(pieces[0].mass == Approx(6e-6).epsilon(1e-12));
  CHECK((pieces[0].velocity - Vec3(0, 0, -200)).norm() < 1e-12);
  CHECK(pieces[0].nodes.empty());
  const ResidualVelocity r = residualVelocity(m, 0);
  CHECK(r.speed == Approx(200.0).epsilon(1e-12));
  CHECK(r.mass_fraction == Approx(0.6).epsilon(1e-12));
}

TEST_CASE("a projectile has cleared a plate only when its trailing node is past it",
          "[unit][analysis]") {
  // Reference: geometry. A block moving in -z above a plate has not cleared it; the same
  // block below the plate's rear face has.
  const Material steel = fesph::testing::elasticMaterial();
  // with_lead: another projectile (a tandem's lead) 30 mm ahead of the block.
  auto scene = [&](double z0, bool with_lead = false) {
    Model m;
    m.materials.push_back(steel);
    Placement above;
    above.translation = Vec3(0, 0, z0);
    addBody(m, "projectile", structuredBox(Vec3::Zero(), Vec3(1e-3, 1e-3, 2e-3), 1, 1, 2), 0,
            above, Vec3(0, 0, -500), true);
    addBody(m, "plate", structuredBox(Vec3(-5e-3, -5e-3, -1e-3), Vec3(10e-3, 10e-3, 1e-3), 4, 4, 1),
            0, Placement{}, Vec3::Zero(), false);
    if (with_lead) {
      Placement ahead;
      ahead.translation = Vec3(0, 0, z0 - 30e-3);
      addBody(m, "lead", structuredBox(Vec3::Zero(), Vec3(1e-3, 1e-3, 2e-3), 1, 1, 2), 0, ahead,
              Vec3(0, 0, -500), true);
    }
    finaliseModel(m);
    return m;
  };
  REQUIRE_FALSE(residualVelocity(scene(1e-3), 0).cleared);
  REQUIRE(residualVelocity(scene(-5e-3), 0).cleared);
  // Another projectile ahead (a tandem's lead) is no target: past the plate, the follower has
  // cleared every target all the same; above it, not yet.
  REQUIRE(scene(-5e-3, true).bodies.size() == 3);
  CHECK(residualVelocity(scene(-5e-3, true), 0).cleared);
  CHECK(residualVelocity(scene(-5e-3, true), 2).cleared);
  CHECK_FALSE(residualVelocity(scene(1e-3, true), 0).cleared);

  // Past means strictly past: a trailing face on the plane of the plate's rear face (z = -1 mm
  // exactly) has not cleared it; the next double beyond has.
  Model m = scene(-5e-3);
  const Body& projectile = m.bodies[0];
  double top = -1;
  for (std::size_t a = projectile.node_begin; a < projectile.node_end; ++a)
    top = std::max(top, m.nodes.x[a].z());
  for (std::size_t a = projectile.node_begin; a < projectile.node_end; ++a)
    if (m.nodes.x[a].z() == top) m.nodes.x[a].z() = -1e-3;
  REQUIRE_FALSE(residualVelocity(m, 0).cleared);
  for (std::size_t a = projectile.node_begin; a < projectile.node_end; ++a)
    if (m.nodes.x[a].z() == -1e-3) m.nodes.x[a].z() = std::nextafter(-1e-3, -1.0);
  REQUIRE(residualVelocity(m, 0).cleared);

  // A node of no live element is no part of the plate, wherever it went: the plate's elements
  // at its corner (x, y, z) = (-5, -5, -1) mm eroded, the node (mass 0 now) far below.
  const Body& plate = m.bodies[1];
  std::size_t corner = plate.node_begin;
  for (std::size_t a = plate.node_begin; a < plate.node_end; ++a)
    if ((m.nodes.x0[a] - Vec3(-5e-3, -5e-3, -1e-3)).norm() < 1e-12) corner = a;
  for (std::size_t e = plate.elem_begin; e < plate.elem_end; ++e)
    for (int a : m.elems.conn[e])
      if (static_cast<std::size_t>(a) == corner && m.elems.status[e] == ElemStatus::Live)
        erodeElement(m, e, Trigger::PlasticStrain);
  REQUIRE(m.nodes.m[corner] == 0);
  m.nodes.x[corner].z() = -50e-3;
  REQUIRE(residualVelocity(m, 0).cleared);

  // A plate made of particles is its particles: the block above the same plate as particles
  // (one per tetrahedron, at their centroids, down to z = -0.75 mm) has not cleared it, nor
  // with its trailing face (2 mm above its position) at z = -0.7 mm; at -0.8 mm it has.
  const auto overParticles = [&](double z0) {
    Model p;
    p.materials.push_back(steel);
    Placement at;
    at.translation = Vec3(0, 0, z0);
    addBody(p, "projectile", structuredBox(Vec3::Zero(), Vec3(1e-3, 1e-3, 2e-3), 1, 1, 2), 0, at,
            Vec3(0, 0, -500), true);
    addParticleBody(p, "plate",
                    structuredBox(Vec3(-5e-3, -5e-3, -1e-3), Vec3(10e-3, 10e-3, 1e-3), 4, 4, 1),
                    0, Placement{}, Vec3::Zero(), false);
    finaliseModel(p);
    return p;
  };
  const Model particles_below = overParticles(-5e-3);
  double lowest = 0;
  for (const Vec3& x : particles_below.particles.x) lowest = std::min(lowest, x.z());
  REQUIRE(lowest == Approx(-0.75e-3).epsilon(1e-12));  // a tet's centroid, a quarter up
  CHECK_FALSE(residualVelocity(overParticles(1e-3), 0).cleared);
  CHECK_FALSE(residualVelocity(overParticles(-2.7e-3), 0).cleared);
  CHECK(residualVelocity(overParticles(-2.8e-3), 0).cleared);
  CHECK(residualVelocity(particles_below, 0).cleared);
}
