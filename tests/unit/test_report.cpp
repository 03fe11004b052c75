// SPDX-License-Identifier: MIT
// `fesph report`: the Table 1 comparison, run table, velocity plot and plate images of runs,
// from their folders.
#include "tests/support/temp_folder.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <sys/wait.h>

namespace fs = std::filesystem;

namespace {

// A shot in free flight at 1000 m/s past two plates beside its path (see
// test_plate_crossings.cpp): v1 = v2 = 1000 m/s exactly, whatever the conversion mode.
const char* kScene = R"(title = "report check"
[simulation]
end_time = 30e-6
[output]
interval = 15e-6
[[bodies]]
name = "shot"
material = "steel_4340"
projectile = true
velocity = [0, 0, -1000]
position = [0, 0, 1e-3]
[bodies.shape]
type = "projectile"
diameter = 4e-3
length = 6e-3
mesh_size = 3e-3
[[bodies]]
name = "first"
material = "A36"
position = [60e-3, 0, -5e-3]
[bodies.shape]
type = "plate"
size_x = 20e-3
size_y = 20e-3
thickness = 4e-3
mesh_size = 8e-3
coarse_size = 8e-3
[[bodies]]
name = "second"
material = "A36"
position = [60e-3, 0, -15e-3]
[bodies.shape]
type = "plate"
size_x = 20e-3
size_y = 20e-3
thickness = 4e-3
mesh_size = 8e-3
coarse_size = 8e-3
[reference]
source = "free flight"
experiment = [800.0, 1250.0]
[reference.published]
"another code" = [1000.0, 1000.0]
)";

int run(const std::string& args) {
  const int status = std::system((std::string(FESPH_BINARY) + " " + args + " > /dev/null 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

std::string read(const fs::path& p) {
  std::ifstream in(p);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

}  // namespace

TEST_CASE("fesph report compares runs with the scene's reference", "[unit][report]") {
  fesph::testing::TempFolder tmp("report");
  const fs::path scene = tmp.path / "scene.toml";
  std::ofstream(scene) << kScene;
  const std::string common = " --materials " + std::string(FESPH_SCENES_DIR) +
                             "/materials.toml --threads 1 --quiet --no-images --out ";
  REQUIRE(run("run " + scene.string() + common + (tmp.path / "fe").string()) == 0);
  REQUIRE(run("run " + scene.string() + common + (tmp.path / "ero").string() +
              " --set conversion.mode='\"erosion\"'") == 0);
  REQUIRE(run("report " + (tmp.path / "fe").string() + " " + (tmp.path / "ero").string() +
              " --out " + (tmp.path / "rep").string()) == 0);

  const std::string md = read(tmp.path / "rep" / "report.md");
  // Table 1: experiment, the published code, both runs, errors (value - exp) / exp.
  CHECK(md.find("| v1 | 800.0 | 1000.0 | +25.0 % | 1000.0 | +25.0 % | 1000.0 | +25.0 % |") !=
        std::string::npos);
  CHECK(md.find("| v2 | 1250.0 | 1000.0 | -20.0 % |") != std::string::npos);
  CHECK(md.find("FE (default, fe)") != std::string::npos);
  CHECK(md.find("erosion 0.4 (default, ero)") != std::string::npos);
  CHECK(md.find("| complete |") != std::string::npos);
  // What got through: the whole shot, at the intact piece's speed.
  CHECK(md.find("| v1 | FE (default, fe) | 1000.0 | 100.0 % | 1000.0 | +25.0 % | 100.0 % |") !=
        std::string::npos);
  CHECK(read(tmp.path / "rep" / "through.csv").find("2,FE (default, fe),1000.0,1,1000.0,1") !=
        std::string::npos);
  const std::string table = read(tmp.path / "rep" / "table1.csv");
  CHECK(table.find("1,800.0,1000.0,1000.0,1000.0") != std::string::npos);
  // One row per run, the plot, and each run's plate images (drawn by the report: the runs had
  // none).
  std::istringstream runs(read(tmp.path / "rep" / "runs.csv"));
  int lines = 0;
  for (std::string l; std::getline(runs, l);) ++lines;
  CHECK(lines == 3);
  CHECK(read(tmp.path / "rep" / "runs.csv").find(",wall_time_s,threads,") != std::string::npos);
  CHECK(md.find("| wall time | threads |") != std::string::npos);
  CHECK(fs::file_size(tmp.path / "rep" / "velocity.png") > 10000);
  for (const char* png : {"run1/first_front.png", "run1/second_rear.png", "run2/first_rear.png"}) {
    CHECK(fs::exists(tmp.path / "rep" / png));
    CHECK(md.find(png) != std::string::npos);
  }
  // No symmetry plane: no word of particles across one.
  CHECK(md.find("Check failed") == std::string::npos);
  CHECK(read(tmp.path / "fe" / "summary.toml").find("across_symmetry") == std::string::npos);
  // A half model's summary counts its particles across the plane (none), and a run with some
  // (one of a fesph before the mirror images) gets the warning in the report.
  REQUIRE(run("run " + scene.string() + common + (tmp.path / "half").string() +
              " --set simulation.symmetry='\"half\"'") == 0);
  const std::string half = read(tmp.path / "half" / "summary.toml");
  CHECK(half.find("particles_across_symmetry = 0\n") != std::string::npos);
  {
    std::string edited;  // the run's own zeros replaced by a run with particles across
    std::istringstream lines(half);
    for (std::string l; std::getline(lines, l);)
      if (l.find("across_symmetry") == std::string::npos) edited += l + "\n";
    edited += "particles_across_symmetry = 7\nparticle_mass_across_symmetry_kg = 0.002\n"
              "particle_mass_fraction_across_symmetry = 0.25\n";
    std::ofstream(tmp.path / "half" / "summary.toml") << edited;
  }
  REQUIRE(run("report " + (tmp.path / "half").string() + " --out " +
              (tmp.path / "rep_half").string()) == 0);
  CHECK(read(tmp.path / "rep_half" / "report.md")
            .find("7 particles (0.002 kg, 25.0 % of the particles' mass) are across the "
                  "symmetry plane") != std::string::npos);

  // A folder that is not a run is bad input.
  CHECK(run("report " + tmp.path.string()) == 2);
}
