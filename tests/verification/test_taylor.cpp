// SPDX-License-Identifier: MIT
// Taylor impact verification of the FE core with large plastic flow: the copper code
// benchmark and the Johnson & Cook (1983) OFHC experiment, with and without average nodal
// pressure (to show the volumetric locking it removes), at two mesh sizes.
#include "core/scene/scene.hpp"
#include "core/solver/step.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

using namespace fesph;

namespace {

struct TaylorResult {
  double length = 0;       ///< final length, m
  double foot_radius = 0;  ///< largest radius of the nodes within 0.5 mm of the wall, m
  double balance = 0;      ///< worst energy balance error over the run
};

TaylorResult runTaylor(const std::string& scene, const std::vector<std::string>& overrides) {
  const Scene sc = loadScene(std::string(FESPH_SCENES_DIR) + "/" + scene, overrides);
  Model m = buildModel(sc);
  TaylorResult r;
  while (m.time < m.controls.end_time * (1 - 1e-12)) {
    step(m, m.controls.end_time);
    r.balance = std::max(r.balance, m.energy.balanceError());
  }
  double zmin = 1e9, zmax = -1e9;
  for (const Vec3& x : m.nodes.x) zmin = std::min(zmin, x.z()), zmax = std::max(zmax, x.z());
  r.length = zmax - zmin;
  for (const Vec3& x : m.nodes.x)
    if (x.z() < zmin + 0.5e-3) r.foot_radius = std::max(r.foot_radius, std::hypot(x.x(), x.y()));
  std::printf("%s %s: length %.3f mm, foot radius %.3f mm, worst energy balance %.2f %%\n",
              scene.c_str(), overrides.empty() ? "" : overrides.back().c_str(), 1e3 * r.length,
              1e3 * r.foot_radius, 100 * r.balance);
  return r;
}

}  // namespace

TEST_CASE("Taylor code benchmark: copper at 227 m/s", "[verification][taylor][slow]") {
  // Reference: code-to-code benchmark (Carina.jl tet15 Taylor README; SPHinXsys): final
  // impact-face radius 7.11-7.22 mm, final length 21.42-21.48 mm. Must hold: radius within
  // 2 % and length within 1 % of that range; energy balance within 1 %.
  for (const char* size : {"bodies.0.shape.mesh_size=0.8e-3", "bodies.0.shape.mesh_size=0.6e-3"}) {
    const TaylorResult r = runTaylor("taylor_benchmark/scene.toml", {size});
    CHECK(r.length > 0.99 * 21.42e-3);
    CHECK(r.length < 1.01 * 21.48e-3);
    CHECK(r.foot_radius > 0.98 * 7.11e-3);
    CHECK(r.foot_radius < 1.02 * 7.22e-3);
    CHECK(r.balance < 0.01);
  }
  // Without ANP the linear tet locks volumetrically: reported next to the above; the foot
  // cannot spread (measured 6.16 mm at 0.6 mm, 13 % under the range).
  const TaylorResult locked =
      runTaylor("taylor_benchmark/scene.toml", {"simulation.average_nodal_pressure=false"});
  CHECK(locked.foot_radius < 0.98 * 7.11e-3);
}

TEST_CASE("Taylor experiment: OFHC copper at 190 m/s (Johnson & Cook 1983)",
          "[verification][taylor][slow]") {
  // Reference: measured final length 16.21 mm and impact-face diameter 13.56 mm. Must hold:
  // length within 3 %, diameter within 6 %; energy balance within 1 %.
  const TaylorResult r = runTaylor("taylor_ofhc_1983/scene.toml", {});
  CHECK(std::abs(r.length - 16.21e-3) < 0.03 * 16.21e-3);
  CHECK(std::abs(2 * r.foot_radius - 13.56e-3) < 0.06 * 13.56e-3);
  CHECK(r.balance < 0.01);
  const TaylorResult locked =
      runTaylor("taylor_ofhc_1983/scene.toml", {"simulation.average_nodal_pressure=false"});
  CHECK(locked.foot_radius < r.foot_radius);  // locking: a smaller foot
}

TEST_CASE("Taylor OFHC bar: the 3D tets agree with an independent 2D axisymmetric code",
          "[verification][taylor][slow]") {
  // Reference: tools/axisym_taylor.cpp, written apart from core (quads in r-z, one-point with
  // hourglass control or selective-reduced, its own JC return), the same constants and
  // 190 m/s. Converged it gives 17.35 mm (16 cells across the radius 17.335 mm, 32 cells
  // 17.353, 48 cells 17.361; foot 14.61 / 14.71 / 14.74 mm). Must hold: the lengths within 1 %
  // and the foot diameters within 4 % (the 2-D code resolves the rim of the foot finer).
  // Both codes miss the test's 16.21 mm by the same 7 %: the JC 1983 constants' rate term,
  // not the discretisation (docs/materials.md).
  const TaylorResult r = runTaylor("taylor_ofhc_1983/scene.toml", {});
  const std::string out = (std::filesystem::temp_directory_path() / "fesph_axisym.txt").string();
  REQUIRE(std::system((std::string(FESPH_AXISYM_BINARY) + " --case ofhc --nr 16 > " + out).c_str()) == 0);
  std::ifstream in(out);
  double length = 0, diameter = 0;
  for (std::string line; std::getline(in, line);) {
    if (line.find("final length") != std::string::npos)
      length = 1e-3 * std::stod(line.substr(line.find_first_of("0123456789")));
    if (const auto at = line.find("diameter "); at != std::string::npos)
      diameter = 1e-3 * std::stod(line.substr(at + 9));
  }
  std::printf("axisymmetric code: length %.3f mm, foot diameter %.3f mm\n", 1e3 * length,
              1e3 * diameter);
  REQUIRE(length > 0);
  CHECK(std::abs(r.length - length) < 0.01 * length);
  CHECK(std::abs(2 * r.foot_radius - diameter) < 0.04 * diameter);
}
