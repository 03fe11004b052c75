// SPDX-License-Identifier: MIT
// Scene reading: bad input gives a located message (file, line) and exit code 2.
#include "core/common/error.hpp"
#include "core/scene/scene.hpp"

#include <catch2/catch.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sys/wait.h>

using namespace fesph;
namespace fs = std::filesystem;

namespace {

const char* kGoodScene = R"(title = "test"
[simulation]
end_time = 1e-6
[[bodies]]
name = "bar"
material = "steel_4340"
velocity = [0, 0, -100]
[bodies.shape]
type = "projectile"
diameter = 4e-3
length = 8e-3
mesh_size = 2e-3
)";

std::string writeScene(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "fesph_scene_tests";
  fs::create_directories(dir);
  const fs::path p = dir / name;
  std::ofstream(p) << text;
  return p.string();
}

std::string library() { return std::string(FESPH_SCENES_DIR) + "/materials.toml"; }

std::string replace(std::string text, const std::string& from, const std::string& to) {
  const auto pos = text.find(from);
  REQUIRE(pos != std::string::npos);
  return text.replace(pos, from.size(), to);
}

// Run `fesph run` on a scene and return its exit code.
int runCli(const std::string& scene) {
  const std::string cmd = std::string(FESPH_BINARY) + " run " + scene + " --materials " +
                          library() + " --out " +
                          (fs::temp_directory_path() / "fesph_scene_tests_out").string() +
                          " --quiet > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace

TEST_CASE("a valid scene loads", "[unit][scene]") {
  const Scene sc = loadScene(writeScene("good.toml", kGoodScene), {}, library());
  REQUIRE(sc.bodies.size() == 1);
  REQUIRE(sc.controls.end_time == 1e-6);
  REQUIRE(sc.bodies[0].velocity.z() == -100);
}

TEST_CASE("a scene named without its folder finds a material library", "[unit][scene]") {
  // `fesph run scene.toml` in the scene's folder: "scene.toml" has an empty parent path, on
  // which the library search threw std::filesystem's error (the run aborted).
  const fs::path dir = fs::path(writeScene("bare.toml", kGoodScene)).parent_path();
  const fs::path before = fs::current_path();
  fs::current_path(dir);
  std::string found;
  CHECK_NOTHROW(found = loadScene("bare.toml").material_library);
  fs::current_path(before);
  REQUIRE(fs::exists(found));
}

TEST_CASE("a typo'd key is an error at its line", "[unit][scene]") {
  const std::string path =
      writeScene("typo.toml", replace(kGoodScene, "end_time = 1e-6", "end_tme = 1e-6"));
  try {
    loadScene(path, {}, library());
    FAIL("no error");
  } catch (const InputError& e) {
    REQUIRE(e.file() == path);
    REQUIRE(e.line() == 3);
    REQUIRE(std::string(e.what()).find("did you mean 'end_time'") != std::string::npos);
  }
  REQUIRE(runCli(path) == 2);
}

TEST_CASE("an unknown material is an error at its line", "[unit][scene]") {
  const std::string path =
      writeScene("material.toml", replace(kGoodScene, "steel_4340", "unobtainium"));
  try {
    loadScene(path, {}, library());
    FAIL("no error");
  } catch (const InputError& e) {
    REQUIRE(e.line() == 6);
    REQUIRE(std::string(e.what()).find("unknown material 'unobtainium'") != std::string::npos);
  }
  REQUIRE(runCli(path) == 2);
}

TEST_CASE("a negative density is rejected before any work", "[unit][scene]") {
  const std::string path = writeScene(
      "density.toml", std::string(kGoodScene) + "[materials.steel_4340]\ndensity = -7850.0\n");
  try {
    loadScene(path, {}, library());
    FAIL("no error");
  } catch (const InputError& e) {
    REQUIRE(e.line() == 14);
    REQUIRE(std::string(e.what()).find("density") != std::string::npos);
  }
  REQUIRE(runCli(path) == 2);
}

TEST_CASE("impossible values are rejected with their line", "[unit][scene]") {
  struct Case {
    std::string from, to;
    int line;
  };
  for (const Case& c : {Case{"end_time = 1e-6", "end_time = -1.0", 3},
                        Case{"length = 8e-3", "length = 0.0", 11},
                        Case{"velocity = [0, 0, -100]", "velocity = [0, -100]", 7},
                        // a name is a file name and a column: it wrote ../x_front.png
                        Case{"name = \"bar\"", "name = \"../bar\"", 5},
                        Case{"name = \"bar\"", "name = \"a bar\"", 5},
                        Case{"name = \"bar\"", "name = \"\"", 5}}) {
    const std::string path = writeScene("impossible.toml", replace(kGoodScene, c.from, c.to));
    try {
      loadScene(path, {}, library());
      FAIL("no error for " << c.to);
    } catch (const InputError& e) {
      INFO(e.what());
      REQUIRE(e.line() == c.line);
    }
  }
}

TEST_CASE("two symmetry planes on one axis are an error at the second", "[unit][scene]") {
  // Mirror images of mirror images across two parallel planes never end.
  const std::string plane = "\n[[boundary]]\ntype = \"symmetry\"\naxis = \"y\"\nposition = 0.0\n";
  for (const auto& [text, line] :
       {std::pair{kGoodScene + plane + plane, 21},
        std::pair{replace(kGoodScene, "end_time = 1e-6", "end_time = 1e-6\nsymmetry = \"half\"") +
                      plane,
                  17}}) {
    const std::string path = writeScene("two_planes.toml", text);
    try {
      loadScene(path, {}, library());
      FAIL("no error for two planes normal to y");
    } catch (const InputError& e) {
      INFO(e.what());
      REQUIRE(e.line() == line);
      REQUIRE(std::string(e.what()).find("one per axis") != std::string::npos);
    }
  }
  const Scene x_and_y = loadScene(
      writeScene("x_and_y.toml", kGoodScene + plane + replace(plane, "\"y\"", "\"x\"")), {},
      library());
  REQUIRE(x_and_y.symmetry.size() == 2);
}

// A plate below kGoodScene's bar (nose at z = 0, pointing down) with its front face at z.
std::string withPlateAt(double z) {
  return std::string(kGoodScene) + R"([[bodies]]
name = "plate"
material = "steel_4340"
position = [0, 0, )" + std::to_string(z) + R"(]
[bodies.shape]
type = "plate"
size_x = 12e-3
size_y = 12e-3
thickness = 2e-3
mesh_size = 2e-3
coarse_size = 2e-3
)";
}

TEST_CASE("bodies that overlap at the start are refused with their lines", "[unit][scene]") {
  // The plate's front face 1 mm below the nose: apart. 1 mm above it: the bar's nose is in
  // the plate (a sign typo in a position), which the first contact passes would throw out.
  const Scene apart = loadScene(writeScene("apart.toml", withPlateAt(-1e-3)), {}, library());
  REQUIRE_NOTHROW(buildModel(apart));
  const std::string path = writeScene("overlap.toml", withPlateAt(1e-3));
  const Scene sc = loadScene(path, {}, library());
  try {
    buildModel(sc);
    FAIL("no error");
  } catch (const InputError& e) {
    INFO(e.what());
    REQUIRE(e.file() == path);
    REQUIRE((e.line() == 4 || e.line() == 13));  // the [[bodies]] of the bar or the plate
    REQUIRE(std::string(e.what()).find("overlap at the start") != std::string::npos);
    REQUIRE(std::string(e.what()).find("'bar'") != std::string::npos);
    REQUIRE(std::string(e.what()).find("'plate'") != std::string::npos);
  }
  REQUIRE(runCli(path) == 2);
}

TEST_CASE("a broken .msh gives a located error and exit code 2", "[unit][scene]") {
  const fs::path dir = fs::temp_directory_path() / "fesph_scene_tests";
  fs::create_directories(dir);
  std::ofstream(dir / "broken.msh") << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n";
  const std::string path = writeScene(
      "msh.toml", replace(kGoodScene,
                          "type = \"projectile\"\ndiameter = 4e-3\nlength = 8e-3\nmesh_size = 2e-3",
                          "type = \"msh\"\nfile = \"broken.msh\""));
  const Scene sc = loadScene(path, {}, library());
  try {
    buildModel(sc);
    FAIL("no error");
  } catch (const InputError& e) {
    INFO(e.what());
    REQUIRE(e.file().find("broken.msh") != std::string::npos);
    REQUIRE(e.line() > 0);
  }
  REQUIRE(runCli(path) == 2);
}

TEST_CASE("scene overrides from the command line are checked like the file", "[unit][scene]") {
  const std::string path = writeScene("set.toml", kGoodScene);
  const Scene sc = loadScene(path, {"simulation.end_time=3e-6", "bodies.0.velocity=[0,0,-5]"},
                             library());
  REQUIRE(sc.controls.end_time == 3e-6);
  REQUIRE(sc.bodies[0].velocity.z() == -5);
  REQUIRE_THROWS_AS(loadScene(path, {"simulation.end_tme=3e-6"}, library()), InputError);
  REQUIRE_THROWS_AS(loadScene(path, {"bodies.4.velocity=[0,0,-5]"}, library()), InputError);
  // A bad value from --set has no line in the file: the error names the --set instead.
  try {
    loadScene(path, {"simulation.end_time=3e-6", "bodies.bar.shape.length=-1"}, library());
    FAIL("no error");
  } catch (const InputError& e) {
    INFO(e.what());
    REQUIRE(e.line() == 0);
    REQUIRE(std::string(e.what()).find("(given by --set bodies.bar.shape.length=-1)") !=
            std::string::npos);
  }
}

TEST_CASE("the command line end time keeps its precision", "[unit][scene]") {
  // Regression: --end-time 1e-7 once reached the scene as "0.000000" and was rejected.
  const std::string path = writeScene("endtime.toml", kGoodScene);
  const std::string cmd = std::string(FESPH_BINARY) + " run " + path + " --materials " +
                          library() + " --end-time 1e-7 --no-images --quiet --out " +
                          (fs::temp_directory_path() / "fesph_scene_tests_endtime").string() +
                          " > /dev/null 2>&1";
  const int status = std::system(cmd.c_str());
  REQUIRE(WIFEXITED(status));
  REQUIRE(WEXITSTATUS(status) == 0);
}

TEST_CASE("resolution presets apply their keys, and --set wins over them", "[unit][scene]") {
  const std::string text = std::string(kGoodScene) + R"(
[resolutions.quick]
"bodies.bar.shape.mesh_size" = 3e-3
"simulation.end_time" = 5e-7
[resolutions.fine]
"bodies.0.shape.mesh_size" = 1e-3
)";
  const std::string path = writeScene("resolutions.toml", text);
  const auto mesh_size = [](const Scene& sc) {
    return std::get<ProjectileSpec>(sc.bodies[0].shape).mesh_size;
  };
  const Scene plain = loadScene(path, {}, library());
  CHECK(plain.resolution == "default");
  CHECK(mesh_size(plain) == 2e-3);
  const Scene quick = loadScene(path, {"resolution=\"quick\""}, library());
  CHECK(quick.resolution == "quick");
  CHECK(mesh_size(quick) == 3e-3);  // by body name
  CHECK(quick.controls.end_time == 5e-7);
  CHECK(mesh_size(loadScene(path, {"resolution=\"fine\""}, library())) == 1e-3);  // by index
  const Scene mixed =
      loadScene(path, {"resolution=\"quick\"", "simulation.end_time=2e-6"}, library());
  CHECK(mixed.controls.end_time == 2e-6);  // the command line wins over the preset

  // An unknown preset names the line of `resolution` and the presets there are.
  const std::string bad = writeScene("bad_resolution.toml", "resolution = \"coarse\"\n" + text);
  try {
    loadScene(bad, {}, library());
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.line() == 1);
    CHECK(std::string(e.what()).find("unknown resolution 'coarse'") != std::string::npos);
    CHECK(std::string(e.what()).find("quick") != std::string::npos);
    CHECK(std::string(e.what()).find("fine") != std::string::npos);
  }
  // A preset key that leads nowhere names the preset's line.
  const std::string wrong = writeScene(
      "bad_preset.toml", std::string(kGoodScene) + "[resolutions.quick]\n\"bodies.7.x\" = 1\n");
  try {
    loadScene(wrong, {"resolution=\"quick\""}, library());
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(e.line() == 14);  // kGoodScene has 12 lines, then the table header
    CHECK(std::string(e.what()).find("'7' is neither an index") != std::string::npos);
  }
}

TEST_CASE("the scene as run reloads to the same scene", "[unit][scene]") {
  // scene.toml of a run folder is Scene::text: overrides and the resolution preset applied,
  // numbers at round-trip precision, so that it reruns (or restarts) exactly what ran.
  const std::string path = writeScene(
      "as_run.toml", std::string(kGoodScene) + "[resolutions.quick]\n\"simulation.end_time\" = 3e-7\n");
  const Scene sc = loadScene(
      path, {"resolution=\"quick\"", "bodies.bar.velocity=[0, 0.1, -123.456789012345]"}, library());
  const std::string copy = writeScene("as_run_copy.toml", sc.text);
  const Scene again = loadScene(copy, {}, library());
  CHECK(again.resolution == "quick");
  CHECK(again.controls.end_time == sc.controls.end_time);
  CHECK(again.controls.end_time == 3e-7);
  CHECK(again.bodies[0].velocity == sc.bodies[0].velocity);
  CHECK(again.bodies[0].velocity.z() == -123.456789012345);
  // The same document, apart from the first line that says where it came from.
  const auto body = [](const std::string& t) { return t.substr(t.find('\n')); };
  CHECK(body(again.text) == body(sc.text));
  CHECK(sc.source.find("velocity = [0, 0, -100]") != std::string::npos);
}

TEST_CASE("[reference] needs one positive velocity per plate", "[unit][scene]") {
  const std::string plate = R"(
[[bodies]]
name = "plate"
material = "A36"
position = [0, 0, -5e-3]
[bodies.shape]
type = "plate"
size_x = 20e-3
size_y = 20e-3
thickness = 2e-3
mesh_size = 2e-3
)";
  const std::string base = std::string(kGoodScene) + plate;
  const Scene ok = loadScene(writeScene("ref_ok.toml", base + "[reference]\nexperiment = [900.5]\n"
                                                             "[reference.published]\n\"x\" = [1e3]\n"),
                             {}, library());
  CHECK(ok.reference.experiment == std::vector<double>{900.5});
  REQUIRE(ok.reference.published.size() == 1);
  CHECK(ok.reference.published[0].first == "x");
  for (const char* bad : {"experiment = [900.5, 800.0]", "experiment = [-3.0]",
                          "experiment = 900.5"}) {
    INFO(bad);
    try {
      loadScene(writeScene("ref_bad.toml", base + "[reference]\n" + bad + "\n"), {}, library());
      FAIL("no error");
    } catch (const InputError& e) {
      CHECK(e.line() == 25);  // 12 lines, a blank, the plate's 10, [reference], the value
    }
  }
}
