// SPDX-License-Identifier: MIT
// Element erosion (the plain-FEM baseline): failed elements are deleted, their mass and
// energy are booked as lost, and the budget still closes.
#include "core/material/library.hpp"
#include "core/solver/step.hpp"
#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

using namespace fesph;

TEST_CASE("erosion deletes failed elements and books their mass and energy",
          "[unit][erosion][conservation]") {
  // Reference: conservation of mass (exact up to round-off, 1e-12) and of energy with the
  // eroded term in the budget (issue criterion: balance within 1%).
  const MaterialLibrary lib = MaterialLibrary::load(std::string(FESPH_SCENES_DIR) + "/materials.toml");
  Model m = fesph::testing::boxModel(lib.get("copper_taylor_benchmark"),
                                     Vec3(4e-3, 4e-3, 16e-3), 4, 4, 16, Vec3(0, 0, -227));
  m.walls.push_back(RigidWall{});
  m.controls.conversion.mode = ConversionMode::Erosion;
  m.controls.conversion.plastic_strain = 0.3;
  double mass0 = 0;
  for (double x : m.nodes.m) mass0 += x;

  double worst = 0;
  while (m.time < 20e-6) {
    step(m, 20e-6);
    worst = std::max(worst, m.energy.balanceError());
  }
  double mass = 0;
  for (double x : m.nodes.m) mass += x;
  long live = 0;
  for (ElemStatus s : m.elems.status) live += s == ElemStatus::Live;
  INFO("eroded " << m.conversion.eroded << " elements, " << m.conversion.eroded_mass
                 << " kg; eroded energy " << m.energy.eroded << " J; worst balance " << worst);
  REQUIRE(m.conversion.eroded > 10);
  REQUIRE(live + m.conversion.eroded == static_cast<long>(m.elems.size()));
  REQUIRE(std::abs(mass + m.conversion.eroded_mass - mass0) < 1e-12 * mass0);
  REQUIRE(m.energy.eroded > 0);
  REQUIRE(worst < 0.01);
  // no eroded element contributes force: all retired nodes have zero mass and stay put
  for (std::size_t a = 0; a < m.nodes.size(); ++a)
    if (m.nodes.m[a] == 0) REQUIRE(m.nodes.f[a].norm() == 0);
}
