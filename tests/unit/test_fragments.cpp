// SPDX-License-Identifier: MIT
// Pieces of a body and the residual velocity of its largest intact piece.
#include "core/analysis/fragments.hpp"
#include "core/contact/surfaces.hpp"
#include "core/conversion/erosion.hpp"
#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

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
}

TEST_CASE("a projectile has cleared a plate only when its trailing node is past it",
          "[unit][analysis]") {
  // Reference: geometry. A block moving in -z above a plate has not cleared it; the same
  // block below the plate's rear face has.
  const Material steel = fesph::testing::elasticMaterial();
  auto scene = [&](double z0) {
    Model m;
    m.materials.push_back(steel);
    Placement above;
    above.translation = Vec3(0, 0, z0);
    addBody(m, "projectile", structuredBox(Vec3::Zero(), Vec3(1e-3, 1e-3, 2e-3), 1, 1, 2), 0,
            above, Vec3(0, 0, -500), true);
    addBody(m, "plate", structuredBox(Vec3(-5e-3, -5e-3, -1e-3), Vec3(10e-3, 10e-3, 1e-3), 4, 4, 1),
            0, Placement{}, Vec3::Zero(), false);
    finaliseModel(m);
    return m;
  };
  REQUIRE_FALSE(residualVelocity(scene(1e-3), 0).cleared);
  REQUIRE(residualVelocity(scene(-5e-3), 0).cleared);
}
