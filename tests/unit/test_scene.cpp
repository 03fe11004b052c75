// SPDX-License-Identifier: MIT
// Scene reading: bad input gives a located message (file, line) and exit code 2.
#include "core/common/error.hpp"
#include "core/scene/scene.hpp"
#include "tests/support/text.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iomanip>
#include <optional>
#include <sstream>
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

// The InputError that `load` throws; none when it throws none.
std::optional<InputError> thrownBy(const std::function<void()>& load) {
  try {
    load();
  } catch (const InputError& e) {
    return e;
  }
  return std::nullopt;
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
  const auto error = thrownBy([&] { loadScene(path, {}, library()); });
  REQUIRE(error);
  REQUIRE(error->file() == path);
  REQUIRE(error->line() == 3);
  REQUIRE(std::string(error->what()).find("did you mean 'end_time'") != std::string::npos);
  REQUIRE(runCli(path) == 2);
}

TEST_CASE("an unknown material is an error at its line", "[unit][scene]") {
  const std::string path =
      writeScene("material.toml", replace(kGoodScene, "steel_4340", "unobtainium"));
  const auto error = thrownBy([&] { loadScene(path, {}, library()); });
  REQUIRE(error);
  REQUIRE(error->line() == 6);
  REQUIRE(std::string(error->what()).find("unknown material 'unobtainium'") != std::string::npos);
  REQUIRE(runCli(path) == 2);
}

TEST_CASE("a scene defines a material of its own, every required key at its line",
          "[unit][scene]") {
  // A material the library does not have, written whole in the scene (it was refused as an
  // unknown material: a scene could only change the library's). Its provenance is required
  // as in the library.
  const std::string aluminium = R"(
[materials.my_aluminium]
status = "assumption"
source = "a handbook's 6061-T6 set, as the user's own"
density = 2700.0
youngs_modulus = 70e9
poisson_ratio = 0.33
[materials.my_aluminium.johnson_cook]
A = 265e6
B = 426e6
n = 0.34
C = 0.015
m = 1.0
[materials.my_aluminium.eos]
type = "mie_gruneisen"
c0 = 5240.0
s = 1.4
gamma0 = 1.97
)";
  const std::string text = replace(kGoodScene, "steel_4340", "my_aluminium") + aluminium;
  const Scene sc = loadScene(writeScene("own_material.toml", text), {}, library());
  REQUIRE(sc.materials.size() == 1);
  const Material& m = sc.materials[0];
  CHECK(m.name == "my_aluminium");
  CHECK(m.rho0 == 2700.0);
  CHECK(m.E == 70e9);
  CHECK(m.A == 265e6);
  CHECK(m.eos == EosModel::MieGruneisen);
  CHECK(m.c0 == 5240.0);
  // G from E and nu (what finaliseMaterial adds to every material).
  CHECK(m.G == Approx(70e9 / (2 * 1.33)).epsilon(1e-12));
  // The optional keys take the defaults a new library material takes.
  CHECK(m.T_room == Material{}.T_room);
  CHECK(m.taylor_quinney == Material{}.taylor_quinney);

  // A required key left out is named, at the material's table (line 14: [materials.my_aluminium]).
  const std::string path =
      writeScene("own_material_short.toml", replace(text, "youngs_modulus = 70e9\n", ""));
  const auto short_key = thrownBy([&] { loadScene(path, {}, library()); });
  REQUIRE(short_key);
  INFO(short_key->what());
  CHECK(short_key->line() == 14);
  CHECK(short_key->message().find("youngs_modulus") != std::string::npos);
  REQUIRE(runCli(path) == 2);
  // A body's material neither in the library nor in the scene says where it was looked for.
  const std::string typo = writeScene(
      "own_material_typo.toml", replace(text, "material = \"my_aluminium\"", "material = \"my_aluminum\""));
  const auto unknown = thrownBy([&] { loadScene(typo, {}, library()); });
  REQUIRE(unknown);
  INFO(unknown->what());
  CHECK(unknown->line() == 6);
  CHECK(unknown->message().find("unknown material 'my_aluminum': not defined in the scene as "
                                "[materials.my_aluminum], and the library ") == 0);
  // One begun with --set has no line to point at: the message names the material.
  const auto begun = thrownBy([&] {
    loadScene(writeScene("own_material_set.toml", kGoodScene),
              {"materials.alu.density=2700.0", "bodies.bar.material=\"alu\""}, library());
  });
  REQUIRE(begun);
  CHECK(begun->message() == "material 'alu': missing key 'status': expected a string");
}

TEST_CASE("a scene or library that is no file says why", "[unit][scene]") {
  // A folder given as the material library read as an empty file: "the material library
  // defines no materials"; a missing one said only "cannot open file".
  const std::string scene = writeScene("why.toml", kGoodScene);
  const std::string folder = fs::path(scene).parent_path().string();
  const auto error = [](const std::function<void()>& load) {
    const auto e = thrownBy(load);
    return e ? std::string(e->what()) : std::string("no error");
  };
  CHECK(error([&] { loadScene(scene, {}, folder); }) ==
        folder + ": error: cannot read: a folder, not a file");
  CHECK(error([&] { loadScene(scene, {}, folder + "/none.toml"); }) ==
        folder + "/none.toml: error: cannot read: No such file or directory");
  CHECK(error([&] { loadScene(folder, {}, library()); }) ==
        folder + ": error: cannot read the scene: a folder, not a file");
  CHECK(error([&] { loadScene(folder + "/none.toml", {}, library()); }) ==
        folder + "/none.toml: error: cannot read the scene: No such file or directory");
}

TEST_CASE("a negative density is rejected before any work", "[unit][scene]") {
  const std::string path = writeScene(
      "density.toml", std::string(kGoodScene) + "[materials.steel_4340]\ndensity = -7850.0\n");
  const auto error = thrownBy([&] { loadScene(path, {}, library()); });
  REQUIRE(error);
  REQUIRE(error->line() == 14);
  REQUIRE(std::string(error->what()).find("density") != std::string::npos);
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
    INFO(c.to);
    const auto error = thrownBy([&] { loadScene(path, {}, library()); });
    REQUIRE(error);
    INFO(error->what());
    REQUIRE(error->line() == c.line);
  }
  // An output field the series has no array for: said at its line before the meshing, where
  // the series writer said it after the meshing with the file alone.
  const std::string fields = writeScene(
      "unknown_field.toml", std::string(kGoodScene) + "[output]\nfields = [\"stress\",\n  \"strain\"]\n");
  const auto unknown_field = thrownBy([&] { loadScene(fields, {}, library()); });
  REQUIRE(unknown_field);
  CHECK(unknown_field->line() == 15);
  CHECK(unknown_field->message().find(
            "unknown output field \"strain\"; allowed: stress, pressure") == 0);
  // The value as given, where std::to_string printed a small one as "-0.000000".
  const std::string small =
      writeScene("impossible_small.toml", replace(kGoodScene, "end_time = 1e-6", "end_time = -2.5e-9"));
  const auto negative_small = thrownBy([&] { loadScene(small, {}, library()); });
  REQUIRE(negative_small);
  CHECK(negative_small->message() == "'end_time' must be > 0, got -2.5e-09");
  // A nose longer than the body was said by the mesher, with no file or line ("<input>:
  // error: projectile: length must exceed the nose length"): an ogive of crh 2 on 4 mm is
  // 4 sqrt(7) / 2 = 5.29 mm long, a hemisphere 2 mm (a body as long as its nose passed here).
  const auto nose = [&](const std::string& shape, const std::string& length) {
    return thrownBy([&] {
      loadScene(writeScene("impossible_nose.toml",
                           replace(replace(kGoodScene, "length = 8e-3", "length = " + length),
                                   "type = \"projectile\"", "type = \"projectile\"\n" + shape)),
                {}, library());
    });
  };
  const auto ogive = nose("nose = \"ogive\"", "5e-3");
  REQUIRE(ogive);
  CHECK(ogive->line() == 12);  // the length, below the nose line put in
  CHECK(ogive->message() ==
        "'length' (5 mm) must exceed the nose's length (5.292 mm: ogive of crh 2 on 4 mm)");
  CHECK_FALSE(nose("nose = \"ogive\"", "5.3e-3"));
  const auto hemisphere = nose("nose = \"hemispherical\"", "2e-3");
  REQUIRE(hemisphere);
  CHECK(hemisphere->message() ==
        "'length' (2 mm) must exceed the nose's length (2 mm: hemispherical on 4 mm)");
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
    const auto error = thrownBy([&] { loadScene(path, {}, library()); });
    REQUIRE(error);
    INFO(error->what());
    REQUIRE(error->line() == line);
    REQUIRE(std::string(error->what()).find("one per axis") != std::string::npos);
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
  const auto error = thrownBy([&] { buildModel(sc); });
  REQUIRE(error);
  INFO(error->what());
  REQUIRE(error->file() == path);
  REQUIRE((error->line() == 4 || error->line() == 13));  // the bar's or the plate's [[bodies]]
  REQUIRE(std::string(error->what()).find("overlap at the start") != std::string::npos);
  REQUIRE(std::string(error->what()).find("'bar'") != std::string::npos);
  REQUIRE(std::string(error->what()).find("'plate'") != std::string::npos);
  REQUIRE(runCli(path) == 2);
}

TEST_CASE("a model with a symmetry plane holds only bodies on one side of it", "[unit][scene]") {
  // A body meshed whole in a half model (a full .msh with symmetry = "half") was taken as it
  // was: its nodes on the plane held there inside the body, its mass counted once more by
  // the mirror image. The bar (diameter 4 mm about x = 0) against planes normal to x.
  const auto withPlane = [](const std::string& position, const std::string& more = "") {
    return std::string(kGoodScene) + more + "[[boundary]]\ntype = \"symmetry\"\naxis = \"x\"\n" +
           "position = " + position + "\n";
  };
  REQUIRE_NOTHROW(buildModel(loadScene(writeScene("side.toml", withPlane("-3e-3")), {}, library())));
  const std::string across = writeScene("across.toml", withPlane("1e-3"));
  const auto both_sides = thrownBy([&] { buildModel(loadScene(across, {}, library())); });
  REQUIRE(both_sides);
  INFO(both_sides->what());
  CHECK(both_sides->file() == across);
  CHECK(both_sides->line() == 4);  // the bar's [[bodies]]
  CHECK(both_sides->message().find(
            "body 'bar' lies on both sides of the symmetry plane x = 1 mm (x = -2") == 0);
  REQUIRE(runCli(across) == 2);
  // A mesh written with few digits puts its nodes on the plane a hair off it: the 10 mm cube
  // in mm with its face y = 0 written as y = -1e-9 (1e-12 m, a 1e-10 of its size) lies on
  // the plane y = 0 of a half model, those nodes held on it.
  {
    std::istringstream cube(fesph::testing::slurp(fs::path(FESPH_TEST_DATA_DIR) / "cube_v22.msh"));
    std::ostringstream hair;
    bool nodes = false;
    int on_plane = 0;
    for (std::string line; std::getline(cube, line);) {
      std::istringstream words(line);
      std::string id, x, y, z;
      if (nodes && (words >> id >> x >> y >> z) && y == "0") line = id + " " + x + " -1e-9 " + z, ++on_plane;
      if (line == "$Nodes") nodes = true;
      if (line == "$EndNodes") nodes = false;
      hair << line << "\n";
    }
    REQUIRE(on_plane > 0);
    const fs::path dir = fs::path(writeScene("hair.toml", "")).parent_path();
    std::ofstream(dir / "cube_hair.msh") << hair.str();
    const std::string text = replace(
        replace(kGoodScene, "end_time = 1e-6", "end_time = 1e-6\nsymmetry = \"half\""),
        "type = \"projectile\"\ndiameter = 4e-3\nlength = 8e-3\nmesh_size = 2e-3",
        "type = \"msh\"\nfile = \"cube_hair.msh\"\nscale = 1e-3");
    const Model m = buildModel(loadScene(writeScene("hair.toml", text), {}, library()));
    int held = 0;
    for (std::size_t a = 0; a < m.nodes.size(); ++a) held += m.nodes.fix[a] == 0b010;
    CHECK(held == on_plane);
  }
  // A second bar 10 mm along -x: the plane at x = -5 mm has one bar on either side.
  const std::string bar = std::string(kGoodScene).substr(std::string(kGoodScene).find("[[bodies]]"));
  const std::string second =
      replace(replace(bar, "name = \"bar\"", "name = \"second\""), "velocity = [0, 0, -100]",
              "velocity = [0, 0, -100]\nposition = [-10e-3, 0, 0]");
  const std::string apart = writeScene("apart_sides.toml", withPlane("-5e-3", second));
  const auto opposite = thrownBy([&] { buildModel(loadScene(apart, {}, library())); });
  REQUIRE(opposite);
  INFO(opposite->what());
  CHECK(opposite->line() == 13);  // the second bar's [[bodies]]
  CHECK(opposite->message().find("bodies 'bar' (line 4) and 'second' lie on opposite sides of the "
                                 "symmetry plane x = -5 mm (second: x = -12") == 0);
}

TEST_CASE("the meshing log gives each body's size and mass, and warns of an .msh unit slip",
          "[unit][scene]") {
  // cube_v41.msh is a 10 mm cube written in mm. Read at scale 1 it is a 10 m steel cube
  // (7.83e6 kg): a run of no use that nothing else would flag. The log says the size and mass
  // of every body, and warns at the body's line when an .msh body is not between 0.1 mm and
  // 2 m across.
  const auto meshingLog = [](const std::string& name, const std::string& scale_line) {
    const std::string text = replace(
        kGoodScene, "type = \"projectile\"\ndiameter = 4e-3\nlength = 8e-3\nmesh_size = 2e-3",
        "type = \"msh\"\nfile = \"" + std::string(FESPH_TEST_DATA_DIR) + "/cube_v41.msh\"\n" +
            scale_line);
    const std::string path = writeScene(name, text);
    std::ostringstream log;
    buildModel(loadScene(path, {}, library()), &log);
    return std::make_pair(path, log.str());
  };
  const auto [metres, in_m] = meshingLog("unit_m.toml", "");
  INFO(in_m);
  // steel_4340: 7830 kg/m^3 (scenes/materials.toml) times (10 m)^3
  CHECK(in_m.find("body 'bar': 45 nodes, 100 tets, 10000 x 10000 x 10000 mm, 7.83e+06 kg") !=
        std::string::npos);
  CHECK(in_m.find(metres + ":4: warning: body 'bar' measures 10000 mm across (cube_v41.msh at "
                           "scale 1): the scene is in m, so a file in mm needs scale = 1e-3") !=
        std::string::npos);
  const auto [right, in_mm] = meshingLog("unit_mm.toml", "scale = 1e-3");
  INFO(in_mm);
  CHECK(in_mm.find("100 tets, 10 x 10 x 10 mm, 7.83 g, shape quality") != std::string::npos);
  CHECK(in_mm.find("warning") == std::string::npos);
  const auto [tiny, in_um] = meshingLog("unit_um.toml", "scale = 1e-6");
  CHECK(in_um.find(tiny + ":4: warning: body 'bar' measures 0.01 mm across (cube_v41.msh at "
                          "scale 1e-06)") != std::string::npos);
  // A half model's bodies are their halves: the log says so (the mass is the half's).
  std::ostringstream half;
  buildModel(loadScene(writeScene("half_log.toml",
                                  replace(kGoodScene, "end_time = 1e-6",
                                          "end_time = 1e-6\nsymmetry = \"half\"")),
                       {}, library()),
             &half);
  INFO(half.str());
  CHECK(half.str().find("4 x 2 x 8 mm, ") != std::string::npos);
  CHECK(half.str().find(" g (its part on one side of the symmetry plane), shape quality") !=
        std::string::npos);
}

// A scene text loadScene refuses at `line`, saying `says`.
struct Refused {
  std::string scene;
  int line;
  const char* says;
};

void checkRefused(const std::vector<Refused>& cases, const std::string& file) {
  for (const Refused& c : cases) {
    const std::string scene = writeScene(file, c.scene);
    const auto error = thrownBy([&] { loadScene(scene, {}, library()); });
    REQUIRE(error);
    INFO(error->what());
    CHECK(error->line() == c.line);
    CHECK(std::string(error->what()).find(c.says) != std::string::npos);
  }
}

// Two tets sharing a face (z = 0), physical volumes 5 "core" (above) and 7 "jacket" (below).
constexpr const char* kCoreAndJacket =
    "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n3 5 \"core\"\n3 7 \"jacket\"\n"
    "$EndPhysicalNames\n$Nodes\n5\n1 0 0 0\n2 1 0 0\n3 0 1 0\n4 0 0 1\n5 0 0 -1\n$EndNodes\n"
    "$Elements\n2\n1 4 2 5 1 1 2 3 4\n2 4 2 7 1 1 3 2 5\n$EndElements\n";

TEST_CASE("two bodies of one .msh: each its physical volume, of its own material",
          "[unit][scene]") {
  // Two tets sharing a face (z = 0), physical volumes 5 "core" and 7 "jacket": a core of
  // steel and a jacket of copper, touching, from the one file.
  const fs::path dir = fs::temp_directory_path() / "fesph_scene_tests";
  fs::create_directories(dir);
  std::ofstream(dir / "two.msh") << kCoreAndJacket;
  const auto body = [](const std::string& name, const std::string& material,
                       const std::string& physical) {
    return "[[bodies]]\nname = \"" + name + "\"\nmaterial = \"" + material +
           "\"\nprojectile = true\nvelocity = [0, 0, -100]\n[bodies.shape]\ntype = \"msh\"\n"
           "file = \"two.msh\"\nscale = 1e-3\nphysical = " + physical + "\n";
  };
  const std::string head = "title = \"core and jacket\"\n[simulation]\nend_time = 1e-6\n";
  const Model m = buildModel(loadScene(
      writeScene("two.toml", head + body("core", "steel_4340", "\"core\"") +
                                 body("jacket", "OFHC_copper", "7")),
      {}, library()));
  REQUIRE(m.bodies.size() == 2);
  CHECK(m.bodies[0].elem_end - m.bodies[0].elem_begin == 1);
  CHECK(m.bodies[1].elem_end - m.bodies[1].elem_begin == 1);
  CHECK(m.materials[m.bodies[0].material].rho0 == 7830.0);  // scenes/materials.toml
  CHECK(m.materials[m.bodies[1].material].rho0 == 8960.0);
  double core_z = 0, jacket_z = 0;  // the core above the shared face, the jacket below
  for (std::size_t a = m.bodies[0].node_begin; a < m.bodies[0].node_end; ++a)
    core_z = std::max(core_z, m.nodes.x[a].z());
  for (std::size_t a = m.bodies[1].node_begin; a < m.bodies[1].node_end; ++a)
    jacket_z = std::min(jacket_z, m.nodes.x[a].z());
  CHECK(core_z == 1e-3);
  CHECK(jacket_z == -1e-3);
  // A volume the file lacks: said at the body's table, with the volumes it has; a physical
  // that is neither a name nor a tag, at its key.
  const std::string lacks =
      writeScene("two_lacks.toml", head + body("core", "steel_4340", "\"cor\""));
  const auto missing = thrownBy([&] { buildModel(loadScene(lacks, {}, library())); });
  REQUIRE(missing);
  INFO(missing->what());
  CHECK(missing->file() == lacks);
  CHECK(missing->line() == 4);
  CHECK(std::string(missing->what()).find("body 'core': ") != std::string::npos);
  CHECK(missing->message().find("error") == std::string::npos);  // the file's message, once
  CHECK(std::string(missing->what())
            .find("no tetrahedra in the physical volume \"cor\"; the mesh's physical volumes: 5 "
                  "\"core\", 7 \"jacket\"") != std::string::npos);
  for (const char* bad : {"0", "1.5", "\"\""}) {
    const auto error = thrownBy([&] {
      loadScene(writeScene("two_bad.toml", head + body("core", "steel_4340", bad)), {}, library());
    });
    REQUIRE(error);
    CHECK(error->line() == 13);
    CHECK(std::string(error->what()).find("'physical' must be a physical volume's name") !=
          std::string::npos);
  }
}

TEST_CASE("one body of two physical volumes of one .msh: each of its material, tied",
          "[unit][scene]") {
  // The core and jacket above as one bullet: `materials` gives each physical volume its
  // material; the volumes keep the nodes of the face they share (tied, not in contact).
  const fs::path dir = fs::temp_directory_path() / "fesph_scene_tests";
  fs::create_directories(dir);
  std::ofstream(dir / "tied.msh") << kCoreAndJacket;
  const std::string head = "title = \"bullet\"\n[simulation]\nend_time = 1e-6\n";
  const auto bullet = [&](const std::string& materials, const std::string& shape_extra = "") {
    return head + "[[bodies]]\nname = \"bullet\"\n" + materials +
           "\nprojectile = true\nvelocity = [0, 0, -100]\n[bodies.shape]\ntype = \"msh\"\n"
           "file = \"tied.msh\"\nscale = 1e-3\n" + shape_extra;
  };
  const std::string path = writeScene(
      "tied.toml", bullet("materials = { core = \"steel_4340\", 7 = \"OFHC_copper\" }"));
  std::ostringstream log;
  const Model m = buildModel(loadScene(path, {}, library()), &log);
  REQUIRE(m.bodies.size() == 1);
  REQUIRE(m.elems.size() == 2);
  CHECK(m.nodes.size() == 5);  // the shared face's nodes once: tied
  CHECK(m.materials[m.elems.material[0]].rho0 == 7830.0);  // element 1: the core (steel_4340)
  CHECK(m.materials[m.elems.material[1]].rho0 == 8960.0);  // element 2: the jacket (copper)
  const double tet = 1e-9 / 6;  // each tet's volume, m^3
  CHECK(bodyMass(m, 0) == Approx((7830.0 + 8960.0) * tet).epsilon(1e-12));
  INFO(log.str());
  CHECK(log.str().find("body 'bullet': 5 nodes, 2 tets, 1 x 1 x 2 mm, 0.002798 g") !=
        std::string::npos);
  CHECK(log.str().find("    volume 'core': 1 tets of steel_4340, 0.001305 g\n") !=
        std::string::npos);
  CHECK(log.str().find("    volume 7: 1 tets of OFHC_copper, 0.001493 g\n") !=
        std::string::npos);
  // made of particles, one per tet: each of its tet's material
  const Model sph = buildModel(loadScene(
      writeScene("tied_sph.toml",
                 bullet("materials = { core = \"steel_4340\", 7 = \"OFHC_copper\" }\n"
                        "discretisation = \"sph\"")),
      {}, library()));
  REQUIRE(sph.particles.size() == 2);
  CHECK(sph.materials[sph.particles.material[0]].rho0 == 7830.0);
  CHECK(sph.materials[sph.particles.material[1]].rho0 == 8960.0);
  CHECK(sph.particles.m[1] == Approx(8960.0 * tet).epsilon(1e-12));

  // Mistakes, each at its line: both keys ('materials', line 7), 'physical' beside
  // 'materials' (line 13), an unknown material (line 6, at its value), no volume, a value
  // that is no id, a shape that is not a file's, and a volume of the file left without a
  // material (the body's line 4).
  const std::vector<Refused> bad = {
      {bullet("material = \"steel_4340\"\nmaterials = { core = \"steel_4340\" }"), 7,
       "a body has 'material' (one for all of it) or 'materials' (one per physical volume of "
       "its msh file), not both"},
      {bullet("materials = { core = \"steel_4340\", jacket = \"OFHC_copper\" }",
              "physical = \"core\"\n"),
       13, "'physical' makes the body one physical volume of one material"},
      {bullet("materials = { core = \"steel_4340\", jacket = \"OFHC_coper\" }"), 6,
       "unknown material 'OFHC_coper'"},
      {bullet("materials = {}"), 6, "'materials' must give at least one physical volume"},
      {bullet("materials = { core = 3 }"), 6,
       "the material of physical volume 'core' must be a material id (a string)"},
      {head + "[[bodies]]\nname = \"bullet\"\nmaterials = { core = \"steel_4340\" }\n"
              "[bodies.shape]\ntype = \"projectile\"\ndiameter = 4e-3\nlength = 8e-3\n"
              "mesh_size = 2e-3\n",
       6, "this body's shape is a projectile"},
  };
  checkRefused(bad, "tied_bad.toml");
  // The jacket meshed apart, on copies of the shared face's nodes: the two would pass
  // through each other (a body has no contact with itself), refused at the body's line.
  std::ofstream(dir / "untied.msh")
      << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$PhysicalNames\n2\n3 5 \"core\"\n"
         "3 7 \"jacket\"\n$EndPhysicalNames\n$Nodes\n8\n1 0 0 0\n2 1 0 0\n3 0 1 0\n"
         "4 0 0 1\n5 0 0 -1\n6 0 0 0\n7 1 0 0\n8 0 1 0\n$EndNodes\n$Elements\n2\n"
         "1 4 2 5 1 1 2 3 4\n2 4 2 7 1 6 8 7 5\n$EndElements\n";
  std::string untied_text =
      bullet("materials = { core = \"steel_4340\", 7 = \"OFHC_copper\" }");
  untied_text.replace(untied_text.find("tied.msh"), 8, "untied.msh");
  const std::string untied = writeScene("untied.toml", untied_text);
  const auto apart = thrownBy([&] { buildModel(loadScene(untied, {}, library())); });
  REQUIRE(apart);
  INFO(apart->what());
  CHECK(apart->line() == 4);
  CHECK(std::string(apart->what())
            .find("body 'bullet': its volumes 'core' and 7 touch or overlap without sharing "
                  "their nodes (2 faces, the first at (0.3333, 0.3333, 0) mm in the file)") !=
        std::string::npos);
  const std::string partial =
      writeScene("tied_partial.toml", bullet("materials = { core = \"steel_4340\" }"));
  const auto error = thrownBy([&] { buildModel(loadScene(partial, {}, library())); });
  REQUIRE(error);
  INFO(error->what());
  CHECK(error->file() == partial);
  CHECK(error->line() == 4);
  CHECK(std::string(error->what())
            .find("body 'bullet': ") != std::string::npos);
  CHECK(std::string(error->what())
            .find("1 of the mesh's 2 tetrahedra are in none of the physical volumes given a "
                  "material (the first: element 2, line 20); the mesh's physical volumes: 5 "
                  "\"core\", 7 \"jacket\"") != std::string::npos);
}

TEST_CASE("a plate of bonded layers: each of its material, tied, as thick as they are",
          "[unit][scene]") {
  // An RHA face bonded to an aluminium back: `layers` from the front face back, each with its
  // thickness and material. Masses: 10 x 10 x 1 mm of RHA (7850 kg/m^3) 0.785 g, 10 x 10 x 2
  // mm of Al_6061_T6 (2700 kg/m^3) 0.54 g (scenes/materials.toml).
  const std::string head = "title = \"bilayer\"\n[simulation]\nend_time = 1e-6\n";
  const auto plate = [&](const std::string& body_extra, const std::string& shape_extra) {
    return head + "[[bodies]]\nname = \"plate\"\n" + body_extra +
           "[bodies.shape]\ntype = \"plate\"\nsize_x = 10e-3\nsize_y = 10e-3\n"
           "mesh_size = 1e-3\n" + shape_extra;
  };
  const std::string layers =
      "layers = [{ thickness = 1e-3, material = \"RHA\" },\n"
      "          { thickness = 2e-3, material = \"Al_6061_T6\" }]\n";
  const Scene sc = loadScene(writeScene("bilayer.toml", plate("", layers)), {}, library());
  REQUIRE(sc.bodies.size() == 1);
  CHECK(std::get<PlateSpec>(sc.bodies[0].shape).thickness == Approx(3e-3).epsilon(1e-15));
  std::ostringstream log;
  const Model m = buildModel(sc, &log);
  INFO(log.str());
  for (std::size_t e = 0; e < m.elems.size(); ++e) {
    double z = 0;
    for (int n : m.elems.conn[e]) z += 0.25 * m.nodes.x[static_cast<std::size_t>(n)].z();
    CHECK(m.materials[m.elems.material[e]].rho0 == (z > -1e-3 ? 7850.0 : 2700.0));
  }
  CHECK(log.str().find("body 'plate': ") != std::string::npos);
  CHECK(log.str().find("10 x 10 x 3 mm, 1.325 g") != std::string::npos);
  CHECK(log.str().find("\n    layer 1: ") != std::string::npos);
  CHECK(log.str().find(" tets of RHA, 0.785 g\n") != std::string::npos);
  CHECK(log.str().find("\n    layer 2: ") != std::string::npos);
  CHECK(log.str().find(" tets of Al_6061_T6, 0.54 g\n") != std::string::npos);

  const std::vector<Refused> bad = {
      {plate("", layers + "thickness = 3e-3\n"), 13,
       "a plate of layers is as thick as its layers together: leave 'thickness' out"},
      {plate("material = \"RHA\"\n", layers), 6,
       "a plate of layers takes each layer's material from its entry in 'layers': leave "
       "'material' out"},
      {plate("", "layers = []\n"), 11, "'layers' must list the plate's layers from its front"},
      {plate("", "layers = [1e-3]\n"), 11, "each { thickness = m, material = \"id\" }"},
      {plate("", "layers = [{ thickness = 1e-3 }]\n"), 11, "missing key 'material'"},
      {plate("", "layers = [{ thickness = 1e-3, material = \"RHA\" },\n"
                 "          { thickness = 2e-3, material = \"Al_6061\" }]\n"),
       12, "unknown material 'Al_6061'"},
      {plate("", "layers = [{ thickness = 1e-3, material = \"RHA\", bond = true }]\n"), 11,
       "bond"},
      {plate("", "layers = [{ thickness = -1e-3, material = \"RHA\" }]\n"), 11, "thickness"},
  };
  checkRefused(bad, "bilayer_bad.toml");
  // the shipped template: RHA on aluminium
  const Scene shipped =
      loadScene(std::string(FESPH_SCENES_DIR) + "/bilayer_plate/scene.toml", {}, library());
  const auto& spec = std::get<PlateSpec>(shipped.bodies.at(1).shape);
  CHECK(spec.layers == std::vector<double>{2e-3, 3e-3});
  CHECK(spec.thickness == Approx(5e-3).epsilon(1e-15));
  CHECK(shipped.bodies[1].volume_materials == std::vector<std::string>{"RHA", "Al_6061_T6"});
}

TEST_CASE("the particle plate template is a plate made of particles, free at its rim",
          "[unit][scene]") {
  // scenes/particle_plate: the single plate's shot on a plate made of particles, which has
  // no nodes to hold (a rim hold would be refused).
  const Scene sc =
      loadScene(std::string(FESPH_SCENES_DIR) + "/particle_plate/scene.toml", {}, library());
  REQUIRE(sc.bodies.size() == 2);
  CHECK(sc.bodies[0].projectile);
  CHECK(sc.bodies[0].discretisation == Discretisation::Fem);
  CHECK(sc.bodies[1].discretisation == Discretisation::Sph);
  CHECK(sc.fixed.empty());
  CHECK(sc.half);
  CHECK(sc.output.folder == "runs/particle_plate");
}

TEST_CASE("the two fragments template has two projectiles on one plate", "[unit][scene]") {
  // scenes/two_fragments: each projectile is measured at the plate on its own; the faster,
  // listed first, is the one a [reference] would be compared with.
  const Scene sc =
      loadScene(std::string(FESPH_SCENES_DIR) + "/two_fragments/scene.toml", {}, library());
  REQUIRE(sc.bodies.size() == 3);
  CHECK(sc.bodies[0].name == "fast");
  CHECK(sc.bodies[0].projectile);
  CHECK(sc.bodies[1].name == "slow");
  CHECK(sc.bodies[1].projectile);
  CHECK_FALSE(sc.bodies[2].projectile);
  CHECK(std::holds_alternative<PlateSpec>(sc.bodies[2].shape));
  CHECK(sc.bodies[0].velocity.norm() > sc.bodies[1].velocity.norm());
  CHECK(sc.half);
  CHECK(sc.output.folder == "runs/two_fragments");
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
  const auto error = thrownBy([&] { buildModel(sc); });
  REQUIRE(error);
  INFO(error->what());
  REQUIRE(error->file().find("broken.msh") != std::string::npos);
  REQUIRE(error->line() > 0);
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
  // A value that is no TOML (a string without its quotes) is said to be one, with what would do.
  for (const char* bad : {"title=steel plate", "simulation.end_time=3e-6 s", "bodies.0.velocity=[0,0"}) {
    CAPTURE(bad);
    const auto error = thrownBy([&] { loadScene(path, {bad}, library()); });
    REQUIRE(error);
    const std::string value = std::string(bad).substr(std::string(bad).find('=') + 1);
    CHECK(std::string(error->what()).find("--set " + std::string(bad)) != std::string::npos);
    CHECK(std::string(error->what())
              .find("'" + value + "' is not a TOML value: expected a number") != std::string::npos);
  }
  // A bad value from --set has no line in the file: the error names the --set instead.
  const auto set_value = thrownBy([&] {
    loadScene(path, {"simulation.end_time=3e-6", "bodies.bar.shape.length=-1"}, library());
  });
  REQUIRE(set_value);
  INFO(set_value->what());
  REQUIRE(set_value->line() == 0);
  REQUIRE(std::string(set_value->what()).find("(given by --set bodies.bar.shape.length=-1)") !=
          std::string::npos);
  // A typo'd key beside a --set of the key it was meant to be: the typo alone is named (the
  // suggestion's 'end_time' named the good --set too).
  const auto set_typo = thrownBy([&] {
    loadScene(path, {"simulation.end_time=3e-6", "simulation.end_tme=4e-6"}, library());
  });
  REQUIRE(set_typo);
  INFO(set_typo->what());
  CHECK(std::string(set_typo->what()).find("(given by --set simulation.end_tme=4e-6)") !=
        std::string::npos);
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
  // A scene may give "default" a preset of its own: the command line wins over it too.
  const std::string with_default =
      writeScene("default_preset.toml", text + "[resolutions.default]\n\"simulation.end_time\" = 7e-7\n");
  CHECK(loadScene(with_default, {}, library()).controls.end_time == 7e-7);
  CHECK(loadScene(with_default, {"simulation.end_time=2e-6"}, library()).controls.end_time == 2e-6);

  // An unknown preset names the line of `resolution` and the presets there are.
  const std::string bad = writeScene("bad_resolution.toml", "resolution = \"coarse\"\n" + text);
  const auto unknown_preset = thrownBy([&] { loadScene(bad, {}, library()); });
  REQUIRE(unknown_preset);
  CHECK(unknown_preset->line() == 1);
  CHECK(std::string(unknown_preset->what()).find("unknown resolution 'coarse'") !=
        std::string::npos);
  CHECK(std::string(unknown_preset->what()).find("quick") != std::string::npos);
  CHECK(std::string(unknown_preset->what()).find("fine") != std::string::npos);
  // A preset's name labels the run (summary.toml, the report's tables): plain characters only,
  // where a quote in it made summary.toml a file no TOML reader takes.
  const std::string quoted_name = writeScene(
      "quoted_resolution.toml", "resolution = 'a\"b'\n" + text + "[resolutions.'a\"b']\n");
  const auto quoted = thrownBy([&] { loadScene(quoted_name, {}, library()); });
  REQUIRE(quoted);
  CHECK(quoted->line() == 1);
  CHECK(std::string(quoted->what()).find("letters, digits, '_' and '-'") != std::string::npos);
  // A preset key that leads nowhere names the preset's line.
  const std::string wrong = writeScene(
      "bad_preset.toml", std::string(kGoodScene) + "[resolutions.quick]\n\"bodies.7.x\" = 1\n");
  const auto dead_end = thrownBy([&] { loadScene(wrong, {"resolution=\"quick\""}, library()); });
  REQUIRE(dead_end);
  CHECK(dead_end->line() == 14);  // kGoodScene has 12 lines, then the table header
  CHECK(std::string(dead_end->what()).find("'7' is neither an index") != std::string::npos);
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

  // A --set value with a line break in it (a multi-line string) stays within the first line's
  // comment: the scene as run parses, and its title is the one given.
  const Scene titled = loadScene(path, {"title=\"\"\"two\nlines\"\"\""}, library());
  CHECK(titled.title == "two\nlines");
  const std::string titled_copy = writeScene("as_run_titled.toml", titled.text);
  CHECK(loadScene(titled_copy, {}, library()).title == "two\nlines");
}

namespace {

// kGoodScene's bar and, 5 mm below its nose, a plate that names only the keys it must.
const std::string kBarAndPlate = std::string(kGoodScene) + R"([[bodies]]
name = "plate"
material = "A36"
position = [0, 0, -5e-3]
[bodies.shape]
type = "plate"
size_x = 20e-3
size_y = 30e-3
thickness = 2e-3
mesh_size = 2e-3
)";

// The message of the InputError that loading `text` (written to `name`: one name a test, as
// ctest runs the tests side by side) with `set` throws; empty when it loads.
std::string loadError(const std::string& name, const std::string& text,
                      const std::vector<std::string>& set) {
  try {
    loadScene(writeScene(name, text), set, library());
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST_CASE("a fixed boundary that holds no node is refused at its line, and the log counts them",
          "[unit][scene]") {
  // The box given in the plate's own frame (z = +-1 mm) where the plate lies at z = -5 to
  // -7 mm held nothing: the plate flew off, its "fixed" edge and all, without a word.
  const std::string box = "[[boundary]]\ntype = \"fixed\"\nbody = \"plate\"\nwhere = \"box\"\n"
                          "min = [-10e-3, -15e-3, -1e-3]\nmax = [10e-3, 15e-3, 1e-3]\n";
  const std::string missed = writeScene("fixed_missed.toml", kBarAndPlate + box);
  const auto error = thrownBy([&] { buildModel(loadScene(missed, {}, library())); });
  REQUIRE(error);
  INFO(error->what());
  CHECK(error->file() == missed);
  CHECK(error->line() == 23);  // its [[boundary]]
  CHECK(error->message() ==
        "the fixed box from (-10, -15, -1) to (10, 15, 1) mm holds no node of body 'plate', "
        "which spans (-10, -15, -7) to (10, 15, -5) mm (min and max are in m)");
  // so also after a rim hold of the same plate: the box's own nodes count
  const std::string rim = "[[boundary]]\ntype = \"fixed\"\nbody = \"plate\"\nwhere = \"rim\"\n";
  const std::string rim_then_box = writeScene("fixed_rim_missed.toml", kBarAndPlate + rim + box);
  const auto after_rim = thrownBy([&] { buildModel(loadScene(rim_then_box, {}, library())); });
  REQUIRE(after_rim);
  CHECK(after_rim->line() == 27);
  // In the global frame it holds the plate's nodes through its thickness at x >= 8 mm, which
  // the log counts.
  std::ostringstream log;
  const Model m = buildModel(
      loadScene(writeScene("fixed_held.toml",
                           kBarAndPlate + "[[boundary]]\ntype = \"fixed\"\nbody = \"plate\"\n"
                                          "where = \"box\"\nmin = [8e-3, -15e-3, -7e-3]\n"
                                          "max = [10e-3, 15e-3, -5e-3]\n"),
                {}, library()),
      &log);
  std::size_t held = 0;
  for (std::size_t a = m.bodies[1].node_begin; a < m.bodies[1].node_end; ++a)
    held += m.nodes.fix[a] == 0b111;
  REQUIRE(held > 0);
  CHECK(log.str().find("  fixed (box): " + std::to_string(held) + " nodes of 'plate' held\n") !=
        std::string::npos);
  // A body made of particles has no nodes to hold.
  const std::string sph = writeScene(
      "fixed_sph.toml", replace(kBarAndPlate, "name = \"plate\"\n",
                                "name = \"plate\"\ndiscretisation = \"sph\"\n") +
                            "[[boundary]]\ntype = \"fixed\"\nbody = \"plate\"\nwhere = \"rim\"\n");
  const auto particles = thrownBy([&] { buildModel(loadScene(sph, {}, library())); });
  REQUIRE(particles);
  CHECK(particles->line() == 24);
  CHECK(particles->message().find("body 'plate' is made of particles") != std::string::npos);
}

TEST_CASE("[reference] needs one positive velocity per plate", "[unit][scene]") {
  const std::string& base = kBarAndPlate;
  const Scene ok = loadScene(writeScene("ref_ok.toml", base + "[reference]\nexperiment = [900.5]\n"
                                                             "[reference.published]\n\"x\" = [1e3]\n"),
                             {}, library());
  CHECK(ok.reference.experiment == std::vector<double>{900.5});
  REQUIRE(ok.reference.published.size() == 1);
  CHECK(ok.reference.published[0].first == "x");
  for (const char* bad : {"experiment = [900.5, 800.0]", "experiment = [-3.0]",
                          "experiment = 900.5"}) {
    INFO(bad);
    const std::string path = writeScene("ref_bad.toml", base + "[reference]\n" + bad + "\n");
    const auto error = thrownBy([&] { loadScene(path, {}, library()); });
    REQUIRE(error);
    CHECK(error->line() == 24);  // 12 lines, the plate's 10, [reference], the value
  }
}

TEST_CASE("a scene that leaves the optional keys out gets the README's defaults",
          "[unit][scene]") {
  // README.md, "Scenes", states these; each is read from the controls' own defaults
  // (model.hpp, sph_workspace.hpp, mesh.hpp), so a default given twice cannot drift.
  const std::string text = kBarAndPlate + R"([[bodies]]
name = "cube"
material = "steel_4340"
position = [0, 0, -50e-3]
[bodies.shape]
type = "msh"
file = ")" + std::string(FESPH_TEST_DATA_DIR) + R"(/cube_v41.msh"
[[boundary]]
type = "rigid_wall"
point = [0, 0, -0.1]
normal = [0, 0, 2]
)";
  const Scene sc = loadScene(writeScene("defaults.toml", text), {}, library());
  const SolverControls& c = sc.controls;
  CHECK(c.courant == 0.5);
  CHECK(c.bulk_linear == 0.06);
  CHECK(c.bulk_quadratic == 1.5);
  CHECK(c.average_nodal_pressure);
  CHECK(c.anp_element_fraction == 0.01);
  CHECK(c.dt_growth == 1.1);
  CHECK(c.dt_min == 1e-13);
  CHECK(c.contact.passes == 3);
  CHECK(c.contact.friction == 0.0);
  CHECK(c.contact.depth_tolerance == 0.2);
  CHECK(c.conversion.mode == ConversionMode::None);
  CHECK(c.conversion.plastic_strain == 0.4);
  CHECK(c.conversion.min_volume_ratio == 0.05);
  CHECK(c.conversion.max_volume_ratio == 20.0);
  CHECK(c.conversion.min_dt_ratio == 0.1);
  CHECK(sc.sph.kappa == 1.3);
  CHECK(sc.sph.av_alpha == 0.1);
  CHECK(sc.sph.av_beta == 0.5);
  CHECK(sc.sph.artificial_stress);
  CHECK(sc.sph.dt_factor == 0.4);
  CHECK(sc.output.folder == "runs/defaults");
  // A scene.toml is named by its folder: every shipped scene is one, and all of them ran into
  // runs/scene, each run replacing the one before.
  CHECK(loadScene(std::string(FESPH_SCENES_DIR) + "/single_plate/scene.toml", {}, library())
            .output.folder == "runs/single_plate");
  CHECK(loadScene(std::string(FESPH_SCENES_DIR) + "/two_plates_oblique/scene.toml", {},
                  library())
            .output.folder == "runs/two_plates_oblique");
  CHECK(sc.output.interval == 1e-6 / 20);  // a twentieth of the end time
  CHECK(sc.output.fields.empty());
  CHECK(sc.output.history_every == 10);
  CHECK(sc.output.checkpoint_interval == 0.0);
  CHECK(sc.output.checkpoints_kept == 2);
  CHECK_FALSE(sc.half);
  CHECK(sc.symmetry.empty());

  const auto& bar = std::get<ProjectileSpec>(sc.bodies[0].shape);
  CHECK(bar.nose == NoseShape::Flat);
  CHECK(bar.crh == 2.0);
  CHECK(bar.cavity_diameter == 0.0);
  CHECK_FALSE(sc.bodies[1].projectile);
  CHECK(sc.bodies[1].discretisation == Discretisation::Fem);
  CHECK(sc.bodies[1].velocity == Vec3::Zero());
  const auto& plate = std::get<PlateSpec>(sc.bodies[1].shape);
  CHECK(plate.coarse_size == plate.fine_size);  // uniform: no grading
  CHECK(plate.refine_radius == 0.0);
  CHECK(plate.refine_x == 0.0);
  CHECK(plate.refine_y == 0.0);
  CHECK(plate.refine_stretch_x == 1.0);
  CHECK(plate.grade_distance == 0.5 * 30e-3);  // half the larger side
  CHECK(std::get<MshShape>(sc.bodies[2].shape).scale == 1.0);
  REQUIRE(sc.walls.size() == 1);
  CHECK(sc.walls[0].friction == 0.0);
  CHECK(sc.walls[0].normal == Vec3::UnitZ());  // [0, 0, 2] made a unit normal
  CHECK(sc.bodies[0].placement.rotation == Mat3::Identity());
}

TEST_CASE("each bound of a scene value lies where its message puts it", "[unit][scene]") {
  // On the bound (or just inside it) loads, just past it is refused naming the rule; the
  // bounds are the messages' own ("'courant' must be in (0, 1]", ...).
  struct Case {
    std::vector<std::string> set;
    std::string error;  ///< a piece of the message; empty: the scene loads
    std::string extra = "";  ///< text appended to the scene
  };
  const std::string half = "simulation.symmetry=\"half\"";
  const std::string box = "\n[[boundary]]\ntype = \"fixed\"\nbody = \"plate\"\nwhere = \"box\"\n"
                          "min = [-1, -1, -1]\n";
  const std::string plane = "\n[[boundary]]\ntype = \"symmetry\"\naxis = \"x\"\nposition = ";
  const std::vector<Case> cases = {
      {{"simulation.courant=1.0"}, ""},
      {{"simulation.courant=1.000001"}, "'courant' must be in (0, 1]"},
      {{"simulation.anp_element_fraction=1.0"}, ""},
      {{"simulation.anp_element_fraction=0.0"}, ""},
      {{"simulation.anp_element_fraction=1.01"}, "'anp_element_fraction' must be in [0, 1]"},
      {{"simulation.dt_growth=1.0"}, ""},
      {{"simulation.dt_growth=0.999"}, "'dt_growth' must be >= 1"},
      {{"simulation.end_time=inf"}, "'end_time' must be finite"},
      {{"contact.passes=1"}, ""},
      {{"contact.passes=10"}, ""},
      {{"contact.passes=0"}, "'passes' must be 1 to 10"},
      {{"contact.passes=11"}, "'passes' must be 1 to 10"},
      {{"conversion.max_volume_ratio=1.001"}, ""},
      {{"conversion.max_volume_ratio=1.0"}, "min_volume_ratio < 1 < max_volume_ratio"},
      {{"conversion.min_volume_ratio=0.999"}, ""},
      {{"conversion.min_volume_ratio=1.0"}, "min_volume_ratio < 1 < max_volume_ratio"},
      {{"conversion.min_dt_ratio=0.999"}, ""},
      {{"conversion.min_dt_ratio=1.0"}, "'min_dt_ratio' must be < 1"},
      {{"sph.kappa=0.8"}, ""},
      {{"sph.kappa=2.5"}, ""},
      {{"sph.kappa=0.79"}, "'kappa' must be in [0.8, 2.5]"},
      {{"sph.kappa=2.51"}, "'kappa' must be in [0.8, 2.5]"},
      {{"sph.dt_factor=1.0"}, ""},
      {{"sph.dt_factor=1.01"}, "'dt_factor' must be in (0, 1]"},
      {{"output.history_every=1"}, ""},
      {{"output.history_every=0"}, "'history_every' must be >= 1"},
      {{"output.checkpoints_kept=1"}, ""},
      {{"output.checkpoints_kept=0"}, "'checkpoints_kept' must be >= 1"},
      {{"bodies.plate.shape.coarse_size=2e-3"}, ""},
      {{"bodies.plate.shape.coarse_size=1.99e-3"}, "'coarse_size' must be >= 'mesh_size'"},
      {{"bodies.bar.shape.nose=\"ogive\"", "bodies.bar.shape.crh=0.5"}, ""},
      {{"bodies.bar.shape.nose=\"ogive\"", "bodies.bar.shape.crh=0.49"}, "'crh' of an ogive"},
      {{"bodies.bar.shape.nose=\"flatter\""}, "is not one of"},
      // the body longer than its nose (d / 2 = 2 mm): 2 mm passed here and failed the mesher
      {{"bodies.bar.shape.nose=\"hemispherical\"", "bodies.bar.shape.length=2.01e-3"}, ""},
      {{"bodies.bar.shape.nose=\"hemispherical\"", "bodies.bar.shape.length=2e-3"},
       "must exceed the nose's length (2 mm"},
      {{"bodies.bar.shape.cavity_diameter=3.99e-3", "bodies.bar.shape.cavity_start=1e-3",
        "bodies.bar.shape.cavity_end=7.99e-3"},
       ""},
      {{"bodies.bar.shape.cavity_diameter=4e-3", "bodies.bar.shape.cavity_start=1e-3",
        "bodies.bar.shape.cavity_end=7e-3"},
       "'cavity_diameter' must be below 'diameter'"},
      {{"bodies.bar.shape.cavity_diameter=2e-3", "bodies.bar.shape.cavity_start=1e-3",
        "bodies.bar.shape.cavity_end=8e-3"},
       "cavity_start < cavity_end < length"},
      {{"bodies.bar.shape.cavity_diameter=2e-3", "bodies.bar.shape.cavity_start=3e-3",
        "bodies.bar.shape.cavity_end=3e-3"},
       "cavity_start < cavity_end < length"},
      {{"bodies.bar.name=\"bar-1_b\""}, ""},
      {{"bodies.bar.velocity=[0, 0, nan]"}, "'velocity' must hold 3 finite numbers"},
      // A half model keeps its plane y = 0: rotations about y only, nothing moves along y.
      {{half, "bodies.bar.rotation={axis = [0, 1, 0], angle_deg = 25}"}, ""},
      {{half, "bodies.bar.rotation={axis = [1, 0, 0], angle_deg = 25}"},
       "may only rotate about the y axis"},
      {{half, "bodies.bar.position=[0, 1e-9, 0]"}, "may only rotate about the y axis"},
      {{half, "bodies.bar.velocity=[0, 1e-9, -100]"}, "the velocity must have y = 0"},
      {{}, "", box + "max = [1, 1, 1]\n"},
      {{}, "'max' must exceed 'min' in every component", box + "max = [1, -1, 1]\n"},
      {{}, "", plane + "0.0\n"},
      {{}, "one per axis", plane + "0.0\n" + plane + "1e-3\n"},
      {{}, "", "[materials.A36]\ndensity = 7800.0\n"},
      {{}, "'copper_taylor_benchmark' is not used by any body",
       "[materials.copper_taylor_benchmark]\ndensity = 8900.0\n"},
      {{}, "[materials.A36] must be a table", "[materials]\nA36 = 3\n"},
      // typos two edits away (two letters swapped, two letters wrong) still get their
      // suggestion
      {{"simulation.end_tiem=1e-6"}, "did you mean 'end_time'?"},
      {{"simulation.ebd_tine=1e-6"}, "did you mean 'end_time'?"},
      {{}, "'experiment' has 2 values for 1 plate: one residual velocity in m/s after each plate",
       "[reference]\nexperiment = [900.0, 800.0]\n"},
      // 0: the projectile stopped in the plate (a test that perforated only the first plates)
      {{}, "", "[reference]\nexperiment = [0.0]\n"},
      {{}, "'experiment': expected a velocity >= 0 in m/s (0: the projectile stopped in that plate)",
       "[reference]\nexperiment = [-1.0]\n"},
      // a key far from every one gets the list, not the nearest: 'rho0' was "did you mean
      // 'eos'?", 'n' "did you mean 'name'?"
      {{}, "unknown key 'rho0' in material 'A36'; expected one of: name, status, source, density",
       "[materials.A36]\nrho0 = 7800.0\n"},
      {{}, "unknown key 'n' in material 'A36'; expected one of:", "[materials.A36]\nn = 0.3\n"},
  };
  for (const Case& c : cases) {
    std::string set;
    for (const std::string& s : c.set) set += s + " ";
    INFO(set << c.extra);
    const std::string error = loadError("bounds.toml", kBarAndPlate + c.extra, c.set);
    INFO(error);
    if (c.error.empty())
      CHECK(error.empty());
    else
      CHECK(error.find(c.error) != std::string::npos);
  }
}

TEST_CASE("the mesh size limit counts the refined disc and the coarse rest", "[unit][scene]") {
  // At most 50 million tetrahedra a body; a regular tetrahedron of edge h holds h^3/(6 sqrt 2),
  // so a volume V meshed at h takes about V / (h^3/(6 sqrt 2)) of them. A plate refined in a
  // disc of radius refine_radius * max(1, refine_stretch_x) + grade_distance (grade_distance
  // by default half the larger side) counts that disc at mesh_size and all of it at
  // coarse_size. Just under the limit loads, just over it is refused.
  const double limit = 50e6;
  const auto tets = [](double volume, double h) {
    return volume / (h * h * h / (6 * std::sqrt(2.0)));
  };
  const auto shape = [](const std::string& key, double x) {
    std::ostringstream s;
    s << std::setprecision(17) << "bodies.plate.shape." << key << "=" << x;
    return s.str();
  };
  struct Case {
    double size, refine_radius, stretch, coarse;  ///< coarse 0: uniform (coarse = mesh size)
  };
  for (const Case& c : {Case{0.1, 0.0, 1.0, 0.0}, Case{0.4, 0.01, 1.0, 0.02},
                        Case{0.4, 0.01, 2.0, 0.02}}) {
    const double thickness = 0.01, volume = c.size * c.size * thickness;
    const double radius = c.refine_radius * c.stretch + 0.5 * c.size;
    const double fine = c.refine_radius > 0 ? M_PI * radius * radius * thickness : volume;
    REQUIRE(fine <= volume);
    std::vector<std::string> set = {shape("size_x", c.size), shape("size_y", c.size),
                                    shape("thickness", thickness)};
    if (c.coarse > 0) {
      set.push_back(shape("coarse_size", c.coarse));
      set.push_back(shape("refine_radius", c.refine_radius));
      set.push_back(shape("refine_stretch_x", c.stretch));
    }
    // The mesh size at which the fine part and the rest make the limit (tets(V, h) is
    // tets(V, 1) / h^3): a uniform plate counts its volume at the mesh size twice, as the
    // reader does.
    const double at_unit_h = tets(fine, 1.0) + (c.coarse > 0 ? 0.0 : tets(volume, 1.0));
    const double coarse_tets = c.coarse > 0 ? tets(volume, c.coarse) : 0.0;
    const double h_limit = std::cbrt(at_unit_h / (limit - coarse_tets));
    INFO("plate " << c.size << " m, refine radius " << c.refine_radius << ", stretch "
                  << c.stretch << ": limit at mesh_size " << h_limit);
    for (const double factor : {1.01, 0.99}) {
      std::vector<std::string> s = set;
      s.push_back(shape("mesh_size", factor * h_limit));
      const std::string error = loadError("mesh_limit.toml", kBarAndPlate, s);
      INFO(factor << ": " << error);
      if (factor > 1)
        CHECK(error.empty());
      else
        CHECK(error.find("'mesh_size' gives about") != std::string::npos);
    }
  }
}

TEST_CASE("a body's rotation turns it by angle_deg about its axis", "[unit][scene]") {
  // rotation = { axis, angle_deg }: right-handed, in degrees, about the axis through the
  // body's local origin; the axis need not be a unit vector. 90 degrees about z takes x to y;
  // 25 degrees about y (the oblique scene) takes z to (sin 25, 0, cos 25).
  const auto rotated = [](const std::string& rotation, const Vec3& v) {
    const Scene sc = loadScene(writeScene("rotation.toml", kGoodScene),
                               {"bodies.bar.rotation=" + rotation}, library());
    return Vec3(sc.bodies[0].placement.rotation * v);
  };
  CHECK((rotated("{axis = [0, 0, 2], angle_deg = 90}", Vec3::UnitX()) - Vec3::UnitY()).norm() <
        1e-15);
  const double a = 25 * M_PI / 180;
  CHECK((rotated("{axis = [0, 3, 0], angle_deg = 25}", Vec3::UnitZ()) -
         Vec3(std::sin(a), 0, std::cos(a)))
            .norm() < 1e-15);
}

TEST_CASE("fixed boundaries hold the rim and a closed box, and symmetry planes add their bits",
          "[unit][scene]") {
  // A half model (plane y = 0) with a second plane on the plate's rear face (z = -7 mm, all
  // bodies on one side of it): the plate's rim is held in every direction, also where it
  // meets a plane; a box holds the nodes inside it and on its faces (its corner is put on a
  // node of the bar); each plane holds the velocity component normal to it, and a node on both
  // planes (the rear face's edge on y = 0) keeps both.
  const std::string planes =
      std::string("\n[[boundary]]\ntype = \"symmetry\"\naxis = \"z\"\nposition = -7e-3\n") +
      "[[boundary]]\ntype = \"fixed\"\nbody = \"plate\"\nwhere = \"rim\"\n";
  const std::vector<std::string> half = {"simulation.symmetry=\"half\""};
  const Model first =
      buildModel(loadScene(writeScene("fixed.toml", kBarAndPlate + planes), half, library()));
  // a node of the bar off both planes: the box's lower corner
  std::size_t corner = 0;
  for (std::size_t a = first.bodies[0].node_begin; a < first.bodies[0].node_end; ++a)
    if (first.nodes.x[a].x() > 1e-4 && first.nodes.x[a].y() > 1e-4) corner = a;
  REQUIRE(corner > 0);
  const Vec3 lo = first.nodes.x[corner], hi = lo + Vec3::Constant(1e-3);
  std::ostringstream box;
  box << std::setprecision(17) << "[[boundary]]\ntype = \"fixed\"\nbody = \"bar\"\nwhere = \"box\"\n"
      << "min = [" << lo.x() << ", " << lo.y() << ", " << lo.z() << "]\nmax = [" << hi.x() << ", "
      << hi.y() << ", " << hi.z() << "]\n";
  const Model m = buildModel(
      loadScene(writeScene("fixed_box.toml", kBarAndPlate + planes + box.str()), half, library()));
  REQUIRE(m.nodes.x == first.nodes.x);  // the same meshes

  double extent = 0;
  for (const Vec3& x : m.nodes.x) extent = std::max(extent, x.cwiseAbs().maxCoeff());
  const double on_plane = 1e-9 * extent, on_rim = 1e-6 * 30e-3;
  int rim = 0, boxed = 0, both_planes = 0;
  for (std::size_t a = 0; a < m.nodes.size(); ++a) {
    const Vec3& x = m.nodes.x[a];
    std::uint8_t expected = 0;
    if (m.nodes.body[a] == 1 && (std::abs(std::abs(x.x()) - 10e-3) < on_rim ||
                                 std::abs(x.y() - 15e-3) < on_rim)) {
      expected = 0b111;
      ++rim;
    }
    if (m.nodes.body[a] == 0 && (x - lo).minCoeff() >= 0 && (hi - x).minCoeff() >= 0) {
      expected = 0b111;
      ++boxed;
    }
    if (std::abs(x.z() + 7e-3) < on_plane) expected |= 0b100;
    if (std::abs(x.y()) < on_plane) expected |= 0b010;
    both_planes += std::abs(x.z() + 7e-3) < on_plane && std::abs(x.y()) < on_plane;
    INFO("node " << a << " at " << x.transpose());
    CHECK(int(m.nodes.fix[a]) == int(expected));
  }
  CHECK(m.nodes.fix[corner] == 0b111);  // on the box's corner
  CHECK(rim > 0);
  CHECK(boxed > 0);
  CHECK(both_planes > 0);
}

TEST_CASE("a body Gmsh cannot mesh is named at its line", "[unit][scene]") {
  // A plate 1 nm thick: OpenCASCADE gives up. The mesher's message had no file or line
  // ("<input>: error: plate: Gmsh failed: ...").
  const std::string path =
      writeScene("thin.toml", replace(kBarAndPlate, "thickness = 2e-3", "thickness = 1e-9"));
  const auto e = thrownBy([&] { buildModel(loadScene(path, {}, library())); });
  REQUIRE(e);
  INFO(e->what());
  CHECK(e->file() == path);
  CHECK(e->line() == 13);  // the plate's [[bodies]]
  CHECK(e->message().find("body 'plate': plate: Gmsh failed") == 0);
  REQUIRE(runCli(path) == 2);
}
