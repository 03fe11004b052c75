// SPDX-License-Identifier: MIT
// Elastic waves in a long slender bar striking a rigid wall: the compression front travels at
// the bar speed sqrt(E/rho) (elementary bar theory; the bar is 50 times longer than wide), and
// crosses the tied interface of a bar of two materials as their impedances say.
#include "core/mesh/structured_box.hpp"
#include "core/scene/scene.hpp"
#include "core/solver/step.hpp"
#include "tests/support/models.hpp"
#include "tests/support/msh_file.hpp"
#include "tests/support/temp_folder.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <utility>

using namespace fesph;
namespace fs = std::filesystem;

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

TEST_CASE("a bar of two tied materials transmits the wave as their impedances say",
          "[verification][fem]") {
  // Reference: elementary wave theory at a welded interface (Kolsky, Stress Waves in Solids,
  // 1953, ch. 2; Graff, Wave Motion in Elastic Solids, 1975, sec. 1.6): a wave that takes
  // material A from -v0 to rest passes into B with the velocity jump 2 Z_A / (Z_A + Z_B) v0,
  // Z = rho c, c = sqrt(E / rho) (Poisson's ratio 0 makes the 3-D bar the 1-D one). The bar
  // is one body of one .msh, its halves the physical volumes "front" and "rear" with a
  // material each (`materials`), tied at their shared nodes. It strikes a rigid wall at
  // x = 0 with its front half. The velocity behind the transmitted front, at x = 3L/4 between
  // that front and the free end's reflection, is compared with the theory for a steel
  // front on an aluminium rear (the rear rebounds, +0.485 v0) and the reverse (-0.485 v0);
  // one material throughout would leave it at rest. Tolerance 2 % of v0.
  const double L = 100e-3, w = 2e-3, v0 = 10.0;
  const TetMesh box = structuredBox(Vec3::Zero(), Vec3(L, w, w), 100, 2, 2);
  const fesph::testing::TempFolder folder("tied_bar");
  const fs::path& dir = folder.path;
  fesph::testing::writeMshVolumes(dir / "bar.msh", box, {{1, "front"}, {2, "rear"}},
                                  [&](const Vec3& c) { return c.x() < 0.5 * L ? 1 : 2; });
  struct Elastic {
    const char* id;
    double rho, E;
  };
  const Elastic steel{"steel", 7850, 200e9}, aluminium{"aluminium", 2700, 70e9};
  for (const auto& [front, rear] : {std::pair{steel, aluminium}, std::pair{aluminium, steel}}) {
    std::string scene =
        "title = \"two-material bar\"\n[simulation]\nend_time = 40e-6\nbulk_linear = 0\n"
        "bulk_quadratic = 0\n[[bodies]]\nname = \"bar\"\nvelocity = [" + std::to_string(-v0) +
        ", 0, 0]\nmaterials = { front = \"" + front.id + "\", rear = \"" + rear.id +
        "\" }\n[bodies.shape]\ntype = \"msh\"\nfile = \"bar.msh\"\n[[boundary]]\n"
        "type = \"rigid_wall\"\npoint = [0, 0, 0]\nnormal = [1, 0, 0]\n";
    for (const Elastic& m : {steel, aluminium})
      scene += std::string("[materials.") + m.id + "]\nstatus = \"assumption\"\n" +
               "source = \"elastic, for the wave theory\"\ndensity = " + std::to_string(m.rho) +
               "\nyoungs_modulus = " + std::to_string(m.E) + "\npoisson_ratio = 0\n";
    const std::string path = (dir / "bar.toml").string();
    std::ofstream(path) << scene;
    Model m = buildModel(loadScene(path, {}, std::string(FESPH_SCENES_DIR) + "/materials.toml"));
    REQUIRE(m.bodies.size() == 1);
    REQUIRE(m.nodes.size() == box.nodes.size());  // one mesh: the halves share their nodes

    std::vector<std::size_t> station;
    for (std::size_t a = 0; a < m.nodes.size(); ++a)
      if (std::abs(m.nodes.x0[a].x() - 0.75 * L) < 1e-9) station.push_back(a);
    REQUIRE(station.size() == 9);
    const double c_front = std::sqrt(front.E / front.rho), c_rear = std::sqrt(rear.E / rear.rho);
    const double z_front = front.rho * c_front, z_rear = rear.rho * c_rear;
    const double expected = -v0 + 2 * z_front / (z_front + z_rear) * v0;
    // between the transmitted front's passing and the free end's reflection (both ~L/4 away)
    const double t_interface = 0.5 * L / c_front;
    const double from = t_interface + 0.35 * L / c_rear, to = t_interface + 0.65 * L / c_rear;
    double sum = 0, weight = 0;
    while (m.time < to) {
      const double t0 = m.time;
      step(m, to);
      if (t0 < from) continue;
      double v = 0;
      for (std::size_t a : station) v += m.nodes.v[a].x();
      sum += (m.time - t0) * v / static_cast<double>(station.size());
      weight += m.time - t0;
    }
    const double plateau = sum / weight;
    INFO(front.id << " front, " << rear.id << " rear: velocity behind the transmitted front "
                  << plateau << " m/s, theory " << expected << " m/s");
    CHECK(std::abs(plateau - expected) < 0.02 * v0);
  }
}
