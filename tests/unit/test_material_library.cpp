// SPDX-License-Identifier: MIT
// The material library file and its strict reader: contents, provenance, located errors and
// scene overrides.
#include "core/material/library.hpp"

#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

using namespace fesph;

namespace {

const std::string kLibrary = std::string(FESPH_SCENES_DIR) + "/materials.toml";

/// Write `text` to a fresh file in the temp directory and return its path.
std::string writeTemp(const std::string& name, const std::string& text) {
  const auto path = std::filesystem::temp_directory_path() / ("fesph_test_" + name);
  std::ofstream(path) << text;
  return path.string();
}

/// A complete, valid one-material library; line numbers are relied on below.
const char* const kValid = R"(# line 1
[iron]
status = "assumption"
source = "test"
density = 7850.0
youngs_modulus = 200e9
poisson_ratio = 0.29
[iron.johnson_cook]
A = 350e6
B = 275e6
n = 0.36
C = 0.022
m = 1.0
)";

/// Load `text` as a library and return the InputError it raises.
InputError loadError(const std::string& name, const std::string& text) {
  const std::string path = writeTemp(name, text);
  try {
    MaterialLibrary::load(path);
  } catch (const InputError& e) {
    std::filesystem::remove(path);
    return e;
  }
  std::filesystem::remove(path);
  FAIL("no InputError for " << name);
  throw std::logic_error("unreachable");
}

}  // namespace

TEST_CASE("the material library loads with provenance for every entry", "[unit][material]") {
  const MaterialLibrary lib = MaterialLibrary::load(kLibrary);
  // The ids the brief (issue 3) asks for; ids() is sorted.
  const std::vector<std::string> expected = {
      "30CrMnSiNi2A", "A36",           "Al_2024_T3",   "Al_6061_T6",
      "OFHC_copper",  "RHA",           "armco_iron",   "copper_taylor_benchmark",
      "steel_1020",   "steel_4340",    "tungsten_alloy", "weldox_460E"};
  CHECK(lib.ids() == expected);
  for (const std::string& id : lib.ids()) {
    const Material& m = lib.get(id);
    INFO(id);
    CHECK(m.source.size() > 20);
    CHECK((m.status == "published" || m.status == "stand-in" || m.status == "assumption"));
    CHECK(!m.name.empty());
    CHECK(m.G > 0);  // finalised
  }
  // The scene materials without a verified set are marked as stand-ins (materials.md sec. 1).
  for (const char* id : {"steel_1020", "A36", "RHA", "30CrMnSiNi2A"})
    CHECK(lib.get(id).status == "stand-in");
  // Spot values, exact as typed: JC 1983 '1006' set, Steinberg 304 SS EOS.
  const Material& s1020 = lib.get("steel_1020");
  CHECK(s1020.strength == StrengthModel::JohnsonCook);
  CHECK(s1020.A == 350e6);
  CHECK(s1020.C == 0.022);
  CHECK(s1020.damage);
  CHECK(s1020.D3 == -1.22);
  CHECK(s1020.eos == EosModel::MieGruneisen);
  CHECK(s1020.c0 == 4570.0);
  CHECK(!lib.get("30CrMnSiNi2A").damage);
  // Taylor benchmark copper: bilinear, B = E Et/(E - Et) with Et = 100 MPa (1e-12), no rate or
  // temperature effect, linear EOS.
  const Material& cu = lib.get("copper_taylor_benchmark");
  CHECK(cu.B == Approx(117e9 * 100e6 / (117e9 - 100e6)).epsilon(1e-12));
  CHECK(cu.n == 1.0);
  CHECK(flowStress(cu, 0.3, 1e5, 1000.0) == Approx(400e6 + 0.3 * cu.B).epsilon(1e-12));
  CHECK(cu.eos == EosModel::Linear);
  CHECK(lib.contains("RHA"));
  CHECK(!lib.contains("rha"));
  CHECK_THROWS_AS(lib.get("unobtainium"), std::out_of_range);
}

TEST_CASE("material library errors name file, line and the fix", "[unit][material]") {
  SECTION("valid reference text loads") {
    const std::string path = writeTemp("valid.toml", kValid);
    CHECK(MaterialLibrary::load(path).get("iron").A == 350e6);
    std::filesystem::remove(path);
  }
  SECTION("a typo'd key") {
    std::string text = kValid;
    text.replace(text.find("density"), 7, "densty");  // line 5
    const InputError e = loadError("typo.toml", text);
    CHECK(e.line() == 5);
    CHECK(e.column() == 1);
    CHECK(std::string(e.what()).find("fesph_test_typo.toml:5:1") != std::string::npos);
    CHECK(std::string(e.what()).find("did you mean 'density'") != std::string::npos);
  }
  SECTION("a typo'd key in a sub-table") {
    std::string text = kValid;
    text.replace(text.find("\nm = "), 3, "\nmm");  // line 13
    const InputError e = loadError("typo_jc.toml", text);
    CHECK(e.line() == 13);
    CHECK(std::string(e.what()).find("[johnson_cook]") != std::string::npos);
    CHECK(std::string(e.what()).find("did you mean 'm'") != std::string::npos);
  }
  SECTION("negative density, with its line") {
    std::string text = kValid;
    text.replace(text.find("7850.0"), 6, "-7850.0");  // line 5
    const InputError e = loadError("negative.toml", text);
    CHECK(e.line() == 5);
    CHECK(std::string(e.what()).find("density must be > 0") != std::string::npos);
  }
  SECTION("Poisson ratio out of range, with its line") {
    std::string text = kValid;
    text.replace(text.find("0.29"), 4, "0.5");  // line 7
    const InputError e = loadError("nu.toml", text);
    CHECK(e.line() == 7);
  }
  SECTION("Mie-Grueneisen without c0") {
    const InputError e = loadError(
        "mg.toml", std::string(kValid) + "[iron.eos]\ntype = \"mie_gruneisen\"\ns = 1.49\n");
    CHECK(e.line() == 14);  // the [iron.eos] header: c0 is required there
    CHECK(std::string(e.what()).find("c0") != std::string::npos);
  }
  SECTION("missing provenance") {
    std::string text = kValid;
    text.erase(text.find("source = \"test\"\n"), 16);
    const InputError e = loadError("nosource.toml", text);
    CHECK(e.line() == 2);
    CHECK(std::string(e.what()).find("missing key 'source'") != std::string::npos);
  }
  SECTION("a bad status") {
    std::string text = kValid;
    text.replace(text.find("assumption"), 10, "guess");
    const InputError e = loadError("status.toml", text);
    CHECK(e.line() == 3);
  }
  SECTION("a damage table without one of its five constants") {
    // A new [damage] table has no base to take a constant from: each of D1-D5 is required.
    for (const char* missing : {"D1", "D3", "D5"}) {
      std::string table =
          "[iron.damage]\nD1 = 0.05\nD2 = 3.44\nD3 = -2.12\nD4 = 0.002\nD5 = 0.61\n";
      const std::size_t at = table.find(missing);
      table.erase(at, table.find('\n', at) - at + 1);  // the line that sets it
      const InputError e = loadError("damage.toml", std::string(kValid) + table);
      INFO(e.what());
      CHECK(e.line() == 14);  // the [iron.damage] header
      CHECK(std::string(e.what()).find(std::string("missing key '") + missing + "'") !=
            std::string::npos);
    }
  }
  SECTION("c0 on a linear EOS") {
    const InputError e = loadError(
        "lin.toml", std::string(kValid) + "[iron.eos]\ntype = \"linear\"\nc0 = 4570.0\n");
    CHECK(e.line() == 16);
  }
}

TEST_CASE("an override table changes only its keys", "[unit][material]") {
  const MaterialLibrary lib = MaterialLibrary::load(kLibrary);
  const Material& base = lib.get("steel_1020");
  const toml::table t = tomlcheck::parseText(
      "density = 7900.0\n[johnson_cook]\nA = 400e6\n[eos]\ngamma0 = 2.17\n", "scene.toml");
  const Material m = parseMaterial(t, "scene.toml", base, "steel_1020");
  CHECK(m.rho0 == 7900.0);
  CHECK(m.A == 400e6);
  CHECK(m.gamma0 == 2.17);
  // Everything else is the library's, exactly.
  CHECK(m.name == base.name);
  CHECK(m.source == base.source);
  CHECK(m.status == base.status);
  CHECK(m.E == base.E);
  CHECK(m.nu == base.nu);
  CHECK(m.G == base.G);
  CHECK(m.K == base.K);
  CHECK(m.cp == base.cp);
  CHECK(m.T_room == base.T_room);
  CHECK(m.T_melt == base.T_melt);
  CHECK(m.taylor_quinney == base.taylor_quinney);
  CHECK(m.erosion_strain == base.erosion_strain);
  CHECK(m.strength == base.strength);
  CHECK(m.B == base.B);
  CHECK(m.n == base.n);
  CHECK(m.C == base.C);
  CHECK(m.m == base.m);
  CHECK(m.eps_dot0 == base.eps_dot0);
  CHECK(m.damage == base.damage);
  CHECK(m.D1 == base.D1);
  CHECK(m.D2 == base.D2);
  CHECK(m.D3 == base.D3);
  CHECK(m.D4 == base.D4);
  CHECK(m.D5 == base.D5);
  CHECK(m.eos == base.eos);
  CHECK(m.c0 == base.c0);
  CHECK(m.s == base.s);
  // A [johnson_cook] override keeps the base's reference rate where that is not 1/s (Weldox
  // 460 E: 5e-4 /s, Borvik et al.).
  const Material& weldox = lib.get("weldox_460E");
  REQUIRE(weldox.eps_dot0 != 1.0);
  const toml::table jc = tomlcheck::parseText("[johnson_cook]\nA = 500e6\n", "scene.toml");
  const Material w = parseMaterial(jc, "scene.toml", weldox, "weldox_460E");
  CHECK(w.A == 500e6);
  CHECK(w.eps_dot0 == weldox.eps_dot0);
  // The optional values (heat, temperatures, Taylor-Quinney, erosion) too, where the base's
  // are not the fallbacks a new material gets.
  Material odd = base;
  odd.cp = 401.0, odd.T_room = 301.0, odd.T_melt = 1701.0, odd.taylor_quinney = 0.81,
  odd.erosion_strain = 1.7;
  const Material o = parseMaterial(jc, "scene.toml", odd, "steel_1020");
  CHECK(o.cp == odd.cp);
  CHECK(o.T_room == odd.T_room);
  CHECK(o.T_melt == odd.T_melt);
  CHECK(o.taylor_quinney == odd.taylor_quinney);
  CHECK(o.erosion_strain == odd.erosion_strain);
  // An empty override is the base itself; a bad override value is located in the scene file.
  const Material same = parseMaterial(toml::table{}, "scene.toml", base, "steel_1020");
  CHECK(same.A == base.A);
  const toml::table bad = tomlcheck::parseText("\n[johnson_cook]\nn = -0.3\n", "scene.toml");
  try {
    parseMaterial(bad, "scene.toml", base, "steel_1020");
    FAIL("negative n accepted");
  } catch (const InputError& e) {
    CHECK(e.file() == "scene.toml");
    CHECK(e.line() == 3);
  }
}
