// SPDX-License-Identifier: MIT
// debris.csv of a run folder: the free particles of the particle series grouped into clumps,
// with their straight-line strikes on the plates the images show (render/debris_table).
#include "render/debris_table.hpp"
#include "render/series_writer.hpp"

#include "core/mesh/structured_box.hpp"
#include "core/sph/particle_body.hpp"
#include "tests/support/models.hpp"
#include "tests/support/temp_folder.hpp"

#include <catch2/catch.hpp>

#include <fstream>
#include <sstream>

using namespace fesph;
namespace fs = std::filesystem;

namespace {

/// The run's plate images (small) and its debris table at their time: the summary, and the
/// table's first row in `row`.
DebrisSummary debrisOf(const fs::path& run, std::vector<PlateImages>& images, std::string& row) {
  ImageOptions options;
  options.width = 320;
  options.height = 240;
  images = renderPlateImages(run.string(), -1, options, (run / "images").string());
  REQUIRE(images.size() == 1);
  const DebrisSummary s = writeDebrisTable(run.string(), images[0].time, images,
                                           (run / "images").string());
  std::ifstream in(run / "images" / "debris.csv");
  std::string header;
  REQUIRE(std::getline(in, header));
  std::getline(in, row);
  return s;
}

/// A 2 x 2 x 2 lattice of 1 mm particles whose lowest layer is 10 mm above z = 0.
std::vector<Vec3> shotLattice() {
  std::vector<Vec3> x;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 2; ++j)
      for (int i = 0; i < 2; ++i) x.push_back(1e-3 * Vec3(i, j, 10 + k));
  return x;
}

}  // namespace

TEST_CASE("debris table: a clump of free particles on course for a plate", "[unit][render]") {
  // Reference: kinematics. A 2 x 2 x 2 lattice of 1 mm particles (centroid 10.5 mm above the
  // plate's front face z = 0) falls at 200 m/s onto a 40 x 40 x 2 mm plate: one clump of 8,
  // striking after 10.5 mm / 200 m/s = 52.5 us at (0.5, 0.5, 0) mm. A ninth particle beside
  // it is tied to a face of the plate, so it is not debris.
  constexpr double mm = 1e-3;
  Model model;
  model.materials.push_back(testing::elasticMaterial());
  addBody(model, "plate",
          structuredBox(Vec3(-20 * mm, -20 * mm, -2 * mm), Vec3(40 * mm, 40 * mm, 2 * mm), 8, 8, 1),
          0, Placement{}, Vec3::Zero(), false);
  // An element body far off to the side: the plate's extent must not reach it.
  addBody(model, "bullet", structuredBox(Vec3(100 * mm, 0, 5 * mm), Vec3(4 * mm, 4 * mm, 8 * mm), 1, 1, 2),
          0, Placement{}, Vec3::Zero(), true);
  finaliseModel(model);
  std::vector<Vec3> x = shotLattice();
  x.push_back(mm * Vec3(2, 0, 10));
  addParticleBody(model, "shot", x, std::vector<double>(x.size(), mm * mm * mm), 0,
                  Vec3(0, 0, -200), true);
  model.particles.tie.back().face = {0, 1, 2};
  testing::TempFolder dir("debris_table");
  SeriesWriter(dir.path).write(model, 40e-6);
  std::ofstream(dir.path / "scene.toml") << "[[bodies]]\nname = \"plate\"\n"
                                            "[[bodies]]\nname = \"bullet\"\nprojectile = true\n"
                                            "[[bodies]]\nname = \"shot\"\nprojectile = true\n";

  const std::vector<DebrisParticle> debris = readDebris(dir.path.string(), -1);
  REQUIRE(debris.size() == 8);  // the tied one left out
  std::vector<PlateImages> images;
  std::string row;
  const DebrisSummary s = debrisOf(dir.path, images, row);
  const std::vector<TargetPlate> plates = targetPlates(images);
  REQUIRE(plates[0].body == 0);
  CHECK(plates[0].half_u == Approx(20 * mm).epsilon(1e-9));
  CHECK(plates[0].half_v == Approx(20 * mm).epsilon(1e-9));
  CHECK((plates[0].centre - Vec3(0, 0, -1 * mm)).norm() < 1e-9);  // on the mid-plane

  CHECK(s.clumps == 1);
  CHECK(s.strikes == 1);
  INFO(row);
  const double m = model.particles.m[0];
  char expected[160];
  std::snprintf(expected, sizeof expected, "4e-05,shot,1,8,%.6g,%.6g,200,0,0,-200,0.0005,0.0005,0.0105,",
                8 * m, 8 * m);
  CHECK(row.rfind(expected, 0) == 0);
  CHECK(row.find(",plate,5.25e-05,9.25e-05,0.0005,0.0005,") != std::string::npos);
}

TEST_CASE("debris table: a plate made of particles is a target, not debris", "[unit][render]") {
  // The clump of the test above falling on the plate made of particles (1 mm^3 each, 40 x 40
  // x 2 mm, front face z = 0): the plate's particles are the plate (PlateImages::particles),
  // so the one clump is the shot's, and it strikes the plate after 52.5 us at (0.5, 0.5, 0)
  // mm. The plate was listed as a clump of free particles of its own.
  constexpr double mm = 1e-3;
  Model model;
  model.materials.push_back(testing::elasticMaterial());
  std::vector<Vec3> lattice;
  for (int k = 0; k < 2; ++k)
    for (int j = 0; j < 40; ++j)
      for (int i = 0; i < 40; ++i) lattice.push_back(mm * Vec3(i - 19.5, j - 19.5, -k - 0.5));
  addParticleBody(model, "plate", lattice, std::vector<double>(lattice.size(), mm * mm * mm), 0,
                  Vec3::Zero(), false);
  const std::vector<Vec3> x = shotLattice();
  addParticleBody(model, "shot", x, std::vector<double>(x.size(), mm * mm * mm), 0,
                  Vec3(0, 0, -200), true);
  finaliseModel(model);
  testing::TempFolder dir("debris_particle_plate");
  SeriesWriter(dir.path).write(model, 40e-6);
  std::ofstream(dir.path / "scene.toml") << "[[bodies]]\nname = \"plate\"\n"
                                            "[[bodies]]\nname = \"shot\"\nprojectile = true\n";
  std::vector<PlateImages> images;
  std::string row;
  const DebrisSummary s = debrisOf(dir.path, images, row);
  CHECK(images[0].particles.size() == lattice.size());
  CHECK(s.clumps == 1);
  CHECK(s.strikes == 1);
  INFO(row);
  CHECK(row.rfind("4e-05,shot,1,8,", 0) == 0);
  // its front face: the particles' centres at z = -0.5 mm and a radius beyond
  CHECK(row.find(",plate,5.25e-05,9.25e-05,0.0005,0.0005,") != std::string::npos);
}
