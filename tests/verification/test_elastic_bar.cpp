// SPDX-License-Identifier: MIT
// Elastic wave in a long slender bar striking a rigid wall: the compression front travels at
// the bar speed sqrt(E/rho) (elementary bar theory; the bar is 50 times longer than wide).
#include "core/solver/step.hpp"
#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

#include <cmath>

using namespace fesph;

TEST_CASE("elastic bar: the front speed is sqrt(E/rho) within 2%", "[verification][fem]") {
  const double L = 100e-3, w = 2e-3, v0 = 10.0;
  const Material steel = fesph::testing::elasticMaterial(7850, 200e9, 0.3);
  Model m = fesph::testing::boxModel(steel, Vec3(L, w, w), 100, 2, 2, Vec3(-v0, 0, 0));
  RigidWall wall;
  wall.point = Vec3::Zero();
  wall.normal = Vec3::UnitX();
  m.walls.push_back(wall);

  // Station: the cross-section at x = L/2. Front arrival = the time its mean velocity has
  // changed by half of the jump (from -v0 to 0 behind the front).
  std::vector<std::size_t> station;
  for (std::size_t a = 0; a < m.nodes.size(); ++a)
    if (std::abs(m.nodes.x0[a].x() - 0.5 * L) < 1e-9) station.push_back(a);
  REQUIRE(station.size() == 9);
  auto stationVelocity = [&] {
    double s = 0;
    for (std::size_t a : station) s += m.nodes.v[a].x();
    return s / static_cast<double>(station.size());
  };

  const double c_bar = std::sqrt(steel.E / steel.rho0);
  const double arrival = fesph::testing::halfJumpArrival(
      m, v0, 1.5 * (0.5 * L / c_bar), [&] { step(m, 1.0); }, stationVelocity);
  REQUIRE(arrival > 0);
  const double speed = 0.5 * L / arrival;
  INFO("front speed " << speed << " m/s, bar speed " << c_bar << " m/s");
  REQUIRE(std::abs(speed - c_bar) / c_bar < 0.02);
}
