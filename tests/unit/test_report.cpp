// SPDX-License-Identifier: MIT
// `fesph report`: the Table 1 comparison, run table, velocity plot and plate images of runs,
// from their folders; and, on the same two-plate run, the plates' numbers in the shell.
#include "tests/support/temp_folder.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdlib>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <sys/wait.h>
#include <vector>

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

/// The fields of a CSV line as RFC 4180 reads them: a quoted field may hold commas, and a
/// quote inside it is doubled.
std::vector<std::string> csvFields(const std::string& line) {
  std::vector<std::string> fields(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"') {
      fields.back() += '"';
      ++i;
    } else if (c == '"') {
      quoted = !quoted;
    } else if (c == ',' && !quoted) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

/// The rows of a CSV file, each split into its fields; every row as wide as the header.
std::vector<std::vector<std::string>> csvTable(const fs::path& file) {
  std::vector<std::vector<std::string>> rows;
  std::istringstream lines(read(file));
  for (std::string l; std::getline(lines, l);) rows.push_back(csvFields(l));
  for (const auto& row : rows) CHECK(row.size() == rows.front().size());
  return rows;
}

}  // namespace

TEST_CASE("fesph report compares runs with the scene's reference", "[unit][report]") {
  fesph::testing::TempFolder tmp("report");
  const fs::path scene = tmp.path / "scene.toml";
  std::ofstream(scene) << kScene;
  const std::string common = " --materials " + std::string(FESPH_SCENES_DIR) +
                             "/materials.toml --threads 1 --quiet --no-images --out ";
  // fesph run of the scene into tmp/NAME with `options`; fesph report of runs in tmp into tmp/OUT
  const auto runScene = [&](const std::string& name, const std::string& options) {
    return run("run " + scene.string() + common + (tmp.path / name).string() + " " + options);
  };
  const auto report = [&](const std::vector<std::string>& names, const std::string& out) {
    std::string folders;
    for (const std::string& n : names) folders += (tmp.path / n).string() + " ";
    return run("report " + folders + "--out " + (tmp.path / out).string());
  };
  REQUIRE(runScene("fe", "") == 0);
  REQUIRE(runScene("ero", "--set conversion.mode='\"erosion\"'") == 0);
  REQUIRE(report({"fe", "ero"}, "rep") == 0);

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
  // The CSV files a spreadsheet opens: run labels hold commas, so they are quoted.
  const auto through = csvTable(tmp.path / "rep" / "through.csv");
  REQUIRE(through.size() == 5);
  CHECK(through[3] ==
        std::vector<std::string>{"2", "FE (default, fe)", "1000.0", "1", "1000.0", "1", "shot"});
  const auto table = csvTable(tmp.path / "rep" / "table1.csv");
  REQUIRE(table.size() == 3);
  CHECK(table[0] == std::vector<std::string>{"plate", "experiment_m_s", "another code_m_s",
                                             "FE (default, fe)_m_s",
                                             "erosion 0.4 (default, ero)_m_s"});
  CHECK(table[1] == std::vector<std::string>{"1", "800.0", "1000.0", "1000.0", "1000.0"});
  // One row per run, the plot, and each run's plate images (drawn by the report: the runs had
  // none).
  const auto runs = csvTable(tmp.path / "rep" / "runs.csv");
  REQUIRE(runs.size() == 3);
  CHECK(runs[0][9] == "wall_time_s");
  CHECK(runs[1][0] == "FE (default, fe)");
  CHECK(runs[2][1] == (tmp.path / "ero").string());
  CHECK(runs[2].back() == "complete");
  CHECK(md.find("| wall time | threads |") != std::string::npos);
  {  // a run of under a second: its wall time is not "0 s"
    const std::size_t row = md.find("| FE (default, fe) | ", md.find("| wall time | threads |"));
    REQUIRE(row != std::string::npos);
    std::vector<std::string> cells;
    std::istringstream line(md.substr(row, md.find('\n', row) - row));
    for (std::string c; std::getline(line, c, '|');) cells.push_back(c);
    REQUIRE(cells.size() >= 7);
    INFO(cells[6]);
    CHECK(std::stod(cells[6]) > 0);
    CHECK(std::abs(std::stod(cells[6]) - std::stod(runs[1][9])) <= 0.005 + 1e-12);  // 2 decimals
  }
  CHECK(fs::file_size(tmp.path / "rep" / "velocity.png") > 10000);
  for (const char* png : {"run1/first_front.png", "run1/second_rear.png", "run2/first_rear.png"}) {
    CHECK(fs::exists(tmp.path / "rep" / png));
    CHECK(md.find(png) != std::string::npos);
  }
  // Images the user drew of another field into the run's images/ are not the report's damage
  // views: it copied them under "coloured by damage". It draws its own now, and leaves the
  // user's as they are.
  REQUIRE(run("render " + (tmp.path / "fe").string() + " --field plastic_strain --size 64x64") ==
          0);
  REQUIRE(report({"fe"}, "rep_field") == 0);
  CHECK(read(tmp.path / "rep_field" / "run1" / "holes.json").find("\"field\": \"damage\"") !=
        std::string::npos);
  CHECK(read(tmp.path / "fe" / "images" / "holes.json").find("\"field\": \"plastic_strain\"") !=
        std::string::npos);
  // No symmetry plane: no word of particles across one.
  CHECK(md.find("Check failed") == std::string::npos);
  CHECK(read(tmp.path / "fe" / "summary.toml").find("across_symmetry") == std::string::npos);
  // A half model's summary counts its particles across the plane (none), and a run with some
  // (one of a fesph before the mirror images) gets the warning in the report.
  REQUIRE(runScene("half", "--set simulation.symmetry='\"half\"'") == 0);
  const std::string half = read(tmp.path / "half" / "summary.toml");
  CHECK(half.find("particles_across_symmetry = 0\n") != std::string::npos);
  {
    std::string edited;  // the run's own zeros replaced by a run with one particle across
    std::istringstream lines(half);
    for (std::string l; std::getline(lines, l);)
      if (l.find("across_symmetry") == std::string::npos) edited += l + "\n";
    edited += "particles_across_symmetry = 1\nparticle_mass_across_symmetry_kg = 0.002\n"
              "particle_mass_fraction_across_symmetry = 0.25\n";
    std::ofstream(tmp.path / "half" / "summary.toml") << edited;
  }
  REQUIRE(report({"half"}, "rep_half") == 0);
  CHECK(read(tmp.path / "rep_half" / "report.md")
            .find("1 particle (0.002 kg, 25.0 % of the particles' mass) is across the "
                  "symmetry plane") != std::string::npos);

  // A run folder named with a trailing slash is the same run; a run of a scene with more
  // plates than the first run's (its residual velocities: a third row) gets its own rows.
  std::ofstream(tmp.path / "ero" / "residual_velocities.csv", std::ios::app)
      << "3,third,3.1e-05,3.6e-05,900,0,0,-900,0.5,850,0.8,shot\n";
  REQUIRE(run("report " + (tmp.path / "fe").string() + "/ " + (tmp.path / "ero").string() +
              " --out " + (tmp.path / "rep_more").string()) == 0);
  const std::string more = read(tmp.path / "rep_more" / "report.md");
  CHECK(more.find("FE (default, fe) |") != std::string::npos);
  CHECK(more.find("| v3 | - | - | - | - | - | 900.0 | - |") != std::string::npos);
  CHECK(more.find("A - is no value: the run ended (its status and time under Runs) or its piece "
                  "stopped before that plane") != std::string::npos);
  // Its piece (half the mass, at 900 m/s) and all its material through (0.8, at 850 m/s).
  CHECK(more.find("| v3 | erosion 0.4 (default, ero) | 900.0 | 50.0 % | 850.0 | - | 80.0 % |") !=
        std::string::npos);
  CHECK(csvTable(tmp.path / "rep_more" / "through.csv").back() ==
        std::vector<std::string>{"3", "erosion 0.4 (default, ero)", "900.0", "0.5", "850.0", "0.8",
                                 "shot"});

  // A second projectile's rows, as a run with two writes them after the first's: a row of its
  // own under what got through, not compared with the experiment (no error), while the table
  // of v_k stays the first projectile's.
  std::ofstream(tmp.path / "ero" / "residual_velocities.csv", std::ios::app)
      << "1,first,1e-05,1.5e-05,700,0,0,-700,1,600,1,tail\n";
  REQUIRE(report({"ero"}, "rep_two") == 0);
  const std::string two = read(tmp.path / "rep_two" / "report.md");
  CHECK(two.find("erosion 0.4 (default, ero) has 2 projectiles; the table gives the scene's "
                 "first, 'shot'; the next section gives each one.") != std::string::npos);
  CHECK(two.find("| v1 | erosion 0.4 (default, ero) 'tail' | 700.0 | 100.0 % | 600.0 | - | "
                 "100.0 % |") != std::string::npos);
  CHECK(two.find("| v1 | erosion 0.4 (default, ero) 'shot' | ") != std::string::npos);
  CHECK(two.find("| v3 | erosion 0.4 (default, ero) 'shot' | 900.0 | 50.0 % | 850.0 | - | "
                 "80.0 % |") != std::string::npos);
  CHECK(two.find("700.0") == two.rfind("700.0"));  // in that row only
  CHECK(csvTable(tmp.path / "rep_two" / "through.csv")[2] ==
        std::vector<std::string>{"1", "erosion 0.4 (default, ero)", "700.0", "1", "600.0", "1",
                                 "tail"});

  // A run of another experiment (its scene's [reference] another) beside the first: its
  // velocities without errors against the first's experiment (v1 showed +25.0 % against 800
  // m/s it was never measured against), and the report says which runs those are.
  REQUIRE(runScene("other", "--set 'reference.experiment=[900.0, 950.0]'") == 0);
  REQUIRE(report({"fe", "other"}, "rep_other") == 0);
  const std::string other = read(tmp.path / "rep_other" / "report.md");
  CHECK(other.find("| v1 | 800.0 | 1000.0 | +25.0 % | 1000.0 | +25.0 % | 1000.0 | - |") !=
        std::string::npos);
  CHECK(other.find("| v1 | FE (default, other) | 1000.0 | 100.0 % | 1000.0 | - | 100.0 % |") !=
        std::string::npos);
  CHECK(other.find("Runs of another scene than the first (their scene's [reference] differs): "
                   "FE (default, other): \"report check\".") != std::string::npos);
  CHECK(md.find("Runs of another scene") == std::string::npos);  // fe and ero: the same

  // A test that stopped in the second plate (its 0): the run through it has no error there,
  // and says so; a velocity after a stop is refused.
  REQUIRE(runScene("stopped", "--set 'reference.experiment=[800.0, 0.0]'") == 0);
  REQUIRE(report({"stopped"}, "rep_stopped") == 0);
  const std::string stopped = read(tmp.path / "rep_stopped" / "report.md");
  CHECK(stopped.find("| v2 | 0 (stopped) | 1000.0 | through (stopped in the test) | 1000.0 | "
                     "through (stopped in the test) |") != std::string::npos);
  CHECK(read(tmp.path / "rep_stopped" / "table1.csv").find("\n2,0.0,") != std::string::npos);
  CHECK(runScene("after_stop", "--set 'reference.experiment=[0.0, 800.0]'") == 2);

  // A folder whose name holds a quote: its CSV fields quoted, the quote doubled.
  const fs::path quoted = tmp.path / "fe \"x\"";
  fs::copy(tmp.path / "fe", quoted, fs::copy_options::recursive);
  REQUIRE(run("report '" + quoted.string() + "' --out " + (tmp.path / "rep_quote").string()) == 0);
  const auto quoted_runs = csvTable(tmp.path / "rep_quote" / "runs.csv");
  REQUIRE(quoted_runs.size() == 2);
  CHECK(quoted_runs[1][0] == "FE (default, fe \"x\")");
  CHECK(quoted_runs[1][1] == quoted.string());

  // A folder that is not a run is bad input, and so is one run given twice (its columns
  // came twice). Runs in folders of one name elsewhere are told apart by their parents.
  CHECK(run("report " + tmp.path.string()) == 2);
  CHECK(report({"fe", "fe/"}, "rep_twice") == 2);
  fs::create_directories(tmp.path / "elsewhere");
  fs::copy(tmp.path / "fe", tmp.path / "elsewhere" / "fe", fs::copy_options::recursive);
  REQUIRE(report({"fe", "elsewhere/fe"}, "rep_alike") == 0);
  const std::string alike = read(tmp.path / "rep_alike" / "report.md");
  CHECK(alike.find("| FE (default, " + tmp.path.filename().string() + "/fe) |") !=
        std::string::npos);
  CHECK(alike.find("| FE (default, elsewhere/fe) |") != std::string::npos);
}

TEST_CASE("fesph report lists the debris on course for a plate", "[unit][report]") {
  // A small impact with conversion: its images include debris.csv, which the report copies and
  // sums up. The table of striking clumps is then checked on a debris.csv with known rows
  // (the striking clump with the most kinetic energy first, masses in grams of the full model).
  fesph::testing::TempFolder tmp("report_debris");
  const fs::path dir = tmp.path / "impact";
  REQUIRE(run("run " + std::string(FESPH_TEST_DATA_DIR) + "/restart_impact.toml --materials " +
              std::string(FESPH_SCENES_DIR) + "/materials.toml --threads 1 --quiet --out " +
              dir.string() + " --set simulation.end_time=1e-6") == 0);
  REQUIRE(fs::exists(dir / "images" / "debris.csv"));
  REQUIRE(run("report " + dir.string() + " --out " + (tmp.path / "rep").string()) == 0);
  std::istringstream csv(read(tmp.path / "rep" / "run1" / "debris.csv"));
  int clumps = -1;  // not the header
  for (std::string l; std::getline(csv, l);) ++clumps;
  REQUIRE(clumps > 0);
  CHECK(read(tmp.path / "rep" / "report.md")
            .find(": " + std::to_string(clumps) + (clumps == 1 ? " clump" : " clumps") +
                  " of two or more free particles") !=
        std::string::npos);

  const std::string written = read(dir / "images" / "debris.csv");
  const std::string header = written.substr(0, written.find('\n') + 1);
  std::ofstream(dir / "images" / "debris.csv")
      << header
      << "1e-3,plate_1,1,40,0.002,0.002,300,0,0,-300,0,0,0.1,0.9,0.001,5,0,,,,,,,\n"
         "1e-3,plate_1,2,20,0.001,0.002,400,0,0,-400,0.2,0,0.1,0.8,0.001,5,1,plate_2,2.5e-4,"
         "1.25e-3,0.2,0,0,400\n"
         "1e-3,plate_1,3,30,0.0015,0.0015,350,0,0,-350,0.3,0.1,0.1,0.7,0.001,5,0,plate_2,"
         "2.8e-4,1.28e-3,0.3,0.1,0,350\n"
         "1e-3,plate_1,4,80,0.004,0.004,50,0,0,-50,0.1,0.1,0.1,0.6,0.002,5,0,plate_2,"
         "2e-3,3e-3,0.1,0.1,0,50\n"
         "1e-3,plate_1,5,90,0.0265,0.0265,386,0,0,-386,0.2,0.3,0.1,0.88,0.002,5,0,plate_2,"
         "2.09e-3,3.09e-3,0.265,0.314,0,342\n";
  REQUIRE(run("report " + dir.string() + " --out " + (tmp.path / "rep2").string()) == 0);
  const std::string md = read(tmp.path / "rep2" / "report.md");
  INFO(md);
  CHECK(md.find("5 clumps of two or more free particles (linked within 1.5 times the sum of "
                "their radii), 4 of them on a straight course") != std::string::npos);
  // Large energies in whole joules, not 1.97e+03 (an oblique impact's 26.5 g at 386 m/s).
  const std::size_t largest = md.find("| plate_1 | 90 | 26.5 | 386 | 1974 | 0.88 | plate_2 | 3.09 | 265, 314 | 342 |");
  CHECK(largest != std::string::npos);
  // Most kinetic energy first (1/2 m v^2: 160, 91.9 and 5 J), not heaviest first: the 4 g
  // clump drifting at 50 m/s comes last.
  const std::size_t first = md.find("| plate_1 | 20 | 2 | 400 | 160 | 0.80 | plate_2 | 1.25 | 200, 0 | 400 |");
  const std::size_t second = md.find("| plate_1 | 30 | 1.5 | 350 | 91.9 | 0.70 | plate_2 | 1.28 | 300, 100 | 350 |");
  const std::size_t third = md.find("| plate_1 | 80 | 4 | 50 | 5 | 0.60 | plate_2 | 3.00 | 100, 100 | 50 |");
  CHECK(first != std::string::npos);
  CHECK(second != std::string::npos);
  CHECK(third != std::string::npos);
  CHECK(largest < first);
  CHECK(first < second);
  CHECK(second < third);

  // The holes table in mm^2 and mm, from a holes.csv with known rows (a 4 mm hole, and a
  // fragment's 125 mm beside it, told apart by their centres).
  std::ofstream(dir / "images" / "holes.csv")
      << "plate,hole,area_m2,diameter_m,centroid_x_m,centroid_y_m,centroid_z_m,on_symmetry\n"
         "plate_2,1,1.2566e-05,0.004,0,0,-0.01,0\n"
         "plate_2,2,7.0686e-06,0.003,0.125,0.0204,-0.01,0\n";
  REQUIRE(run("report " + dir.string() + " --out " + (tmp.path / "rep_holes").string()) == 0);
  const std::string holes_md = read(tmp.path / "rep_holes" / "report.md");
  INFO(holes_md);
  CHECK(holes_md.find("| plate_2 | 1 | 12.6 | 4.00 | 0.0, 0.0, -10.0 |") != std::string::npos);
  CHECK(holes_md.find("| plate_2 | 2 | 7.1 | 3.00 | 125.0, 20.4, -10.0 |") != std::string::npos);

  // A table that is not fesph's (a hand-edited number) is an error naming it, not a crash.
  std::ofstream(dir / "images" / "debris.csv")
      << header << "1e-3,plate_1,1,20,0.001,0.002,fast,0,0,-400,0.2,0,0.1,0.8,0.001,5,1,plate_2,"
                   "2.5e-4,1.25e-3,0.2,0,0,400\n";
  CHECK(run("report " + dir.string() + " --out " + (tmp.path / "rep3").string()) == 1);
}

TEST_CASE("the shell names a run's plates by number, projectiles left out", "[unit][report]") {
  // The report's two-plate run: plate 2 is "second".
  fesph::testing::TempFolder tmp("report_plates");
  const fs::path scene = tmp.path / "scene.toml";
  std::ofstream(scene) << kScene;
  REQUIRE(run("run " + scene.string() + " --materials " + std::string(FESPH_SCENES_DIR) +
              "/materials.toml --threads 1 --quiet --no-images --out " + (tmp.path / "fe").string()) ==
          0);
  std::ofstream(tmp.path / "render.txt") << "render plate 2\n";
  REQUIRE(run("shell " + (tmp.path / "fe").string() + " < " + (tmp.path / "render.txt").string()) ==
          0);
  std::vector<std::string> drawn;
  for (const auto& entry : fs::recursive_directory_iterator(tmp.path / "fe" / "shell"))
    if (entry.path().extension() == ".png") drawn.push_back(entry.path().filename().string());
  std::sort(drawn.begin(), drawn.end());
  CHECK(drawn == std::vector<std::string>{"second_front.png", "second_rear.png"});
}
