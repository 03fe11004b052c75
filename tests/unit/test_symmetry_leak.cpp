// SPDX-License-Identifier: MIT
// Particles across a half model's symmetry plane are counted on the side away from the nodes.
#include "core/analysis/symmetry_leak.hpp"

#include <catch2/catch.hpp>

using namespace fesph;

TEST_CASE("particles across a symmetry plane: counted on the side away from the model",
          "[unit][analysis]") {
  Model m;
  // nodes on the plane y = 0 and on its +y side: the model's side is +y
  m.nodes.x = {Vec3(0, 0, 0), Vec3(1e-3, 2e-3, 0), Vec3(0, 5e-3, 1e-3)};
  m.particles.x = {Vec3(0, 1e-3, 0), Vec3(0, -1e-3, 0), Vec3(0, 0, 0), Vec3(0, -4e-3, 0)};
  m.particles.m = {1e-3, 2e-3, 4e-3, 8e-3};
  const std::vector<SymmetryPlane> planes = {{1, 0.0}};
  const std::vector<SymmetryLeak> leaks = particlesAcrossSymmetry(m, planes);
  REQUIRE(leaks.size() == 1);
  CHECK(leaks[0].plane == &planes[0]);
  CHECK(leaks[0].particles == 2);  // the two at y < 0; the one on the plane is not across
  CHECK(leaks[0].mass == Approx(10e-3).epsilon(1e-15));
  CHECK(leaks[0].mass_fraction == Approx(10.0 / 15.0).epsilon(1e-15));

  // The model on the -y side of a plane at y = 3 mm: only the particle above it is across.
  m.nodes.x = {Vec3(0, 3e-3, 0), Vec3(0, -2e-3, 0)};
  m.particles.x.push_back(Vec3(0, 5e-3, 0));
  m.particles.m.push_back(5e-3);
  const std::vector<SymmetryPlane> upper = {{1, 3e-3}};
  const std::vector<SymmetryLeak> up = particlesAcrossSymmetry(m, upper);
  REQUIRE(up.size() == 1);
  CHECK(up[0].particles == 1);
  CHECK(up[0].mass == Approx(5e-3).epsilon(1e-15));

  // A plane whose side the nodes do not tell (all on it: a sheet in the plane) reports
  // nothing, rather than a leak of zero it cannot know; the other plane still reports.
  m.nodes.x = {Vec3(0, 3e-3, 0), Vec3(1e-3, 3e-3, 0), Vec3(0, 3e-3, 1e-3)};
  const std::vector<SymmetryPlane> both = {{1, 3e-3}, {0, -1e-3}};
  const std::vector<SymmetryLeak> told = particlesAcrossSymmetry(m, both);
  REQUIRE(told.size() == 1);
  CHECK(told[0].plane == &both[1]);

  // No particles: nothing across, no division by zero.
  m.nodes.x = {Vec3(0, 3e-3, 0), Vec3(0, -2e-3, 0)};
  m.particles = Particles{};
  const std::vector<SymmetryLeak> none = particlesAcrossSymmetry(m, planes);
  REQUIRE(none.size() == 1);
  CHECK(none[0].particles == 0);
  CHECK(none[0].mass_fraction == 0.0);
}
