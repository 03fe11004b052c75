// SPDX-License-Identifier: MIT
// The residual velocity after each plate is taken where its definition says (plate_crossings.hpp).
#include "core/analysis/fragments.hpp"
#include "core/analysis/plate_crossings.hpp"
#include "core/conversion/convert.hpp"
#include "core/solver/step.hpp"

#include <catch2/catch.hpp>

#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>

using namespace fesph;
namespace fs = std::filesystem;

namespace {

// A projectile in free flight at 1000 m/s past two plates set beside its path: nothing slows it,
// so v_k is 1000 m/s and the crossing times follow from the geometry alone.
const char* kScene = R"(title = "crossings"
[simulation]
end_time = 30e-6
[[bodies]]
name = "shot"
material = "steel_4340"
projectile = true
velocity = [0, 0, -1000]
position = [0, 0, 1e-3]        # nose at z = 1 mm
[bodies.shape]
type = "projectile"
diameter = 4e-3
length = 6e-3
mesh_size = 2e-3
[[bodies]]
name = "second"                # listed first, met second: the order follows the flight
material = "A36"
position = [60e-3, 0, -15e-3]  # front z = -15 mm, 60 mm beside the path
[bodies.shape]
type = "plate"
size_x = 20e-3
size_y = 20e-3
thickness = 2e-3
mesh_size = 5e-3
coarse_size = 5e-3
[[bodies]]
name = "first"
material = "A36"
position = [60e-3, 0, -5e-3]   # front z = -5 mm, rear -7 mm: clear gap 8 mm
[bodies.shape]
type = "plate"
size_x = 20e-3
size_y = 20e-3
thickness = 2e-3
mesh_size = 5e-3
coarse_size = 5e-3
)";

/// The scene above (or `text`), written to a folder of that name under the temporary
/// directory and read.
Scene crossingsScene(const char* folder, const std::string& text = kScene) {
  const fs::path dir = fs::temp_directory_path() / folder;
  fs::create_directories(dir);
  const std::string path = (dir / "scene.toml").string();
  std::ofstream(path) << text;
  return loadScene(path, {}, std::string(FESPH_SCENES_DIR) + "/materials.toml");
}

/// The scene above (crossingsScene) with the elements of the shot's front half (nose at
/// z = 1 mm, tail at 7 mm) converted to particles.
Model shotWithFrontHalfConverted(const char* folder) {
  Model m = buildModel(crossingsScene(folder));
  m.controls.conversion.mode = ConversionMode::Sph;
  const Body& b = m.bodies[0];
  for (std::size_t e = b.elem_begin; e < b.elem_end; ++e) {
    double zc = 0;
    for (int a : m.elems.conn[e]) zc += 0.25 * m.nodes.x[a].z();
    if (zc < 4e-3) m.elems.state[e].eps_p = 1.0;
  }
  REQUIRE(convertElements(m, 1.3) > 0);
  return m;
}

/// Steps `m` to its end time, updating each of `crossings` after every step; the largest
/// step, s.
double runToEnd(Model& m, std::initializer_list<PlateCrossings*> crossings) {
  double dt_max = 0;
  while (m.time < m.controls.end_time * (1 - 1e-12)) {
    step(m, m.controls.end_time);
    dt_max = std::max(dt_max, m.dt);
    for (PlateCrossings* c : crossings) c->update(m);
  }
  return dt_max;
}

}  // namespace

TEST_CASE("residual velocity is taken at the measuring plane of each plate", "[unit][analysis]") {
  const fs::path dir = fs::temp_directory_path() / "fesph_crossings";
  const Scene sc = crossingsScene("fesph_crossings");
  Model m = buildModel(sc);
  PlateCrossings crossings(sc, m, 0);
  REQUIRE(crossings.plates().size() == 2);
  CHECK(crossings.plates()[0].name == "first");
  CHECK(crossings.plates()[1].name == "second");
  // Measuring planes: the clear gap (8 mm) behind each rear face, i.e. z = -15 mm (the front
  // face of the second plate) and z = -25 mm.
  CHECK(crossings.plates()[0].measure_depth == Approx(10e-3));
  const double dt_max = runToEnd(m, {&crossings});
  // The nose (z = 1 mm at t = 0) reaches z = -5, -15, -25 mm at 6, 16 and 26 us; each event is
  // seen at the end of the step in which it happens (within one step).
  const auto& p = crossings.plates();
  CHECK(p[0].t_contact == Approx(6e-6).margin(dt_max));
  CHECK(p[1].t_contact == Approx(16e-6).margin(dt_max));
  CHECK(p[0].t_measured == Approx(16e-6).margin(dt_max));
  CHECK(p[1].t_measured == Approx(26e-6).margin(dt_max));
  for (const PlateCrossing& c : p) {
    CHECK(c.speed == Approx(1000.0).epsilon(1e-9));  // free flight: unchanged
    CHECK(c.mass_fraction == Approx(1.0).epsilon(1e-12));
    // The whole shot is past the rear face by then (its tail, 6 mm behind the nose, too).
    CHECK(c.through_velocity.norm() == Approx(1000.0).epsilon(1e-9));
    CHECK(c.through_mass_fraction == Approx(1.0).epsilon(1e-12));
  }
  writeCrossingsCsv((dir / "rv.csv").string(), {crossings});
  std::ifstream in(dir / "rv.csv");
  std::stringstream ss;
  ss << in.rdbuf();
  CHECK(ss.str().find("1,first,") != std::string::npos);
  CHECK(ss.str().find("2,second,") != std::string::npos);
  CHECK(ss.str().find(",through_velocity_m_s,through_mass_fraction,projectile\n") != std::string::npos);
  CHECK(ss.str().find(",1,shot\n2,second,") != std::string::npos);  // each row names the shot

  // A table that cannot be written is an error naming the file, and the last one stays whole.
  fs::create_directories(dir / "rv.csv.tmp");  // a folder where the temporary must go
  CHECK_THROWS_WITH(writeCrossingsCsv((dir / "rv.csv").string(), {crossings}),
                    Catch::Contains((dir / "rv.csv.tmp").string()));
  std::ifstream again(dir / "rv.csv");
  std::stringstream kept;
  kept << again.rdbuf();
  CHECK(kept.str() == ss.str());
  fs::remove_all(dir / "rv.csv.tmp");
}

TEST_CASE("each projectile of a scene is measured at the plates", "[unit][analysis]") {
  // Reference: plate_crossings.hpp, applied to each projectile. A second one, "slow", flies
  // beside the first at 500 m/s, its nose at z = -3 mm: nothing slows either, so each one's v_k
  // is its own speed, and its events come when its nose has flown to the planes of the scene
  // above: contact with the first plate at z = -5 mm after 4 us, v_1 at -15 mm after 24 us,
  // contact with the second at -15 mm after 24 us, v_2 at -25 mm after 44 us, after the end.
  std::string text = kScene;
  text += R"(
[[bodies]]
name = "slow"
material = "steel_4340"
projectile = true
velocity = [0, 0, -500]
position = [20e-3, 0, -3e-3]
[bodies.shape]
type = "projectile"
diameter = 4e-3
length = 6e-3
mesh_size = 2e-3
)";
  const fs::path dir = fs::temp_directory_path() / "fesph_crossings_two";
  const Scene sc = crossingsScene("fesph_crossings_two", text);
  Model m = buildModel(sc);
  std::vector<PlateCrossings> all = allPlateCrossings(sc, m);
  REQUIRE(all.size() == 2);
  CHECK(all[0].projectileName() == "shot");
  CHECK(all[1].projectileName() == "slow");
  CHECK(all[1].projectile() == 3);
  for (const PlateCrossings& c : all) {  // the plates only: a projectile is no target
    REQUIRE(c.plates().size() == 2);
    CHECK(c.plates()[0].name == "first");
    CHECK(c.plates()[1].name == "second");
  }
  const double dt_max = runToEnd(m, {&all[0], &all[1]});
  for (const PlateCrossing& p : all[0].plates()) CHECK(p.speed == Approx(1000.0).epsilon(1e-9));
  const auto& slow = all[1].plates();
  CHECK(slow[0].t_contact == Approx(4e-6).margin(dt_max));
  CHECK(slow[0].t_measured == Approx(24e-6).margin(dt_max));
  CHECK(slow[0].speed == Approx(500.0).epsilon(1e-9));
  CHECK(slow[0].mass_fraction == Approx(1.0).epsilon(1e-12));
  CHECK(slow[1].t_contact == Approx(24e-6).margin(dt_max));
  CHECK(slow[1].t_measured < 0);

  // residual_velocities.csv: the shot's rows, then the slow one's, each naming its projectile.
  writeCrossingsCsv((dir / "rv.csv").string(), all);
  std::ifstream in(dir / "rv.csv");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string csv = ss.str();
  const std::size_t slow_rows = csv.find("\n1,first,", csv.find(",shot\n2,second,"));
  REQUIRE(slow_rows != std::string::npos);
  CHECK(csv.find(",500,", slow_rows) != std::string::npos);
  CHECK(csv.find(",slow\n2,second,", slow_rows) != std::string::npos);
  const std::string contact_only = ",,,,,,,,,slow\n";  // the last row: nothing measured
  REQUIRE(csv.size() > contact_only.size());
  CHECK(csv.substr(csv.size() - contact_only.size()) == contact_only);
}

TEST_CASE("a projectile made of particles is measured at the plates as one of elements is",
          "[unit][analysis]") {
  // Reference: plate_crossings.hpp and fragments.hpp: a body of particles' intact pieces are its
  // linked particles (debris.hpp's link), its leading point its leading particle. The free
  // flight above with the shot made of particles (one per tetrahedron): nothing slows it, so
  // v_k is 1000 m/s, and each event comes when its leading particle, which starts at depth d0
  // behind the nose's plane z = 1 mm, has flown the distance to its plane.
  std::string text = kScene;
  const std::string tag = "projectile = true\n";
  text.replace(text.find(tag), tag.size(), tag + "discretisation = \"sph\"\n");
  const Scene sc = crossingsScene("fesph_crossings_particles", text);
  Model m = buildModel(sc);
  const Body& shot = m.bodies[0];
  REQUIRE(shot.discretisation == Discretisation::Sph);
  double lead = -1, mass = 0;  // the leading particle's z, m; the shot's mass, kg
  for (std::size_t i = 0; i < m.particles.size(); ++i) {
    REQUIRE(m.particles.body[i] == 0);
    lead = i == 0 ? m.particles.x[i].z() : std::min(lead, m.particles.x[i].z());
    mass += m.particles.m[i];
  }
  REQUIRE(lead > 1e-3);  // a centroid, behind the nose
  CHECK(bodyInitialMass(m, 0) == Approx(mass).epsilon(1e-12));
  // Beside the plates, but behind their nodes along its flight: not clear of them yet.
  CHECK_FALSE(residualVelocity(m, 0).cleared);
  const std::vector<Piece> pieces = bodyPieces(m, 0);
  REQUIRE(pieces.size() == 1);  // the particles of a mesh are linked: one piece
  CHECK(pieces[0].particles.size() == m.particles.size());
  CHECK(pieces[0].mass == Approx(mass).epsilon(1e-12));

  PlateCrossings crossings(sc, m, 0);
  REQUIRE(crossings.plates().size() == 2);
  CHECK(crossings.projectileName() == "shot");
  const double dt_max = runToEnd(m, {&crossings});
  const auto& p = crossings.plates();
  const double to = lead / 1000;  // s, flight time of the leading particle to z = 0
  CHECK(p[0].t_contact == Approx(to + 5e-6).margin(dt_max));   // z = -5 mm
  CHECK(p[0].t_measured == Approx(to + 15e-6).margin(dt_max)); // -15 mm
  CHECK(p[1].t_measured == Approx(to + 25e-6).margin(dt_max)); // -25 mm
  for (const PlateCrossing& c : p) {
    CHECK(c.t_measured > 0);
    CHECK(c.speed == Approx(1000.0).epsilon(1e-9));
    CHECK(c.mass_fraction == Approx(1.0).epsilon(1e-12));
    CHECK(c.through_mass_fraction == Approx(1.0).epsilon(1e-12));
  }
  const ResidualVelocity r = residualVelocity(m, 0);
  CHECK(r.speed == Approx(1000.0).epsilon(1e-9));
  CHECK(r.cleared);  // past both plates' nodes, beside its path
}

TEST_CASE("a continued run keeps the plates measured before it", "[unit][analysis][restart]") {
  // Reference: PlateCrossings(plates, projectile), the table a checkpoint gives back: plates
  // already measured keep their v_k, however far past their measuring planes the shot is now;
  // the first plate not measured is the next to be. The shot of the scene above is moved by
  // hand, its nose past the first plate's plane (-15 mm) only, then past the second's (-25 mm).
  const Scene sc = crossingsScene("fesph_crossings_continued");
  Model m = buildModel(sc);
  std::vector<PlateCrossing> plates = PlateCrossings(sc, m, 0).plates();
  REQUIRE(plates.size() == 2);
  plates[0].t_contact = 4e-6;
  plates[0].t_measured = 5e-6;
  plates[0].velocity = Vec3(0, 0, -777);
  plates[0].speed = 777;
  PlateCrossings continued(plates, 0, "shot");
  CHECK(continued.projectileName() == "shot");
  const Body& shot = m.bodies[0];
  const auto moveShot = [&](double dz) {
    for (std::size_t a = shot.node_begin; a < shot.node_end; ++a) m.nodes.x[a].z() += dz;
  };
  moveShot(-17e-3);  // nose at -16 mm
  m.time = 20e-6;
  continued.update(m);
  CHECK(continued.plates()[0].t_measured == 5e-6);
  CHECK(continued.plates()[0].speed == 777);
  CHECK(continued.plates()[1].t_measured < 0);
  moveShot(-10e-3);  // nose at -26 mm, tail at -20 mm: the whole shot past the rear face
  m.time = 30e-6;
  continued.update(m);
  CHECK(continued.plates()[0].speed == 777);
  CHECK(continued.plates()[1].t_measured == 30e-6);
  CHECK(continued.plates()[1].speed == Approx(1000.0).epsilon(1e-12));
}

TEST_CASE("a projectile that moves away from every plate is told apart", "[unit][analysis]") {
  // Reference: plate_crossings.hpp: headsAway when every plate lies behind the projectile
  // along its velocity. The shot of the scene above towards its plates, then turned round.
  std::string text = kScene;
  const Scene towards = crossingsScene("fesph_crossings_towards", text);
  CHECK_FALSE(PlateCrossings(towards, buildModel(towards), 0).headsAway());
  const std::string v = "velocity = [0, 0, -1000]";
  text.replace(text.find(v), v.size(), "velocity = [0, 0, 1000]");
  const Scene away = crossingsScene("fesph_crossings_away", text);
  const PlateCrossings crossings(away, buildModel(away), 0);
  CHECK(crossings.headsAway());
  CHECK(crossings.plates().size() == 2);
}

TEST_CASE("a node without mass does not touch a plate", "[unit][analysis]") {
  // Reference: plate_crossings.hpp: t_contact is when the projectile's leading live node
  // reaches the front face. A node whose elements are all gone (mass 0, left drifting) is no
  // longer the projectile's: placed past the front face (z = -5 mm) it starts no contact; a
  // node with mass placed there does.
  const Scene sc = crossingsScene("fesph_crossings_massless");
  Model m = buildModel(sc);
  PlateCrossings crossings(sc, m, 0);
  const std::size_t orphan = m.bodies[0].node_begin, live = orphan + 1;
  m.nodes.m[orphan] = 0;
  m.nodes.x[orphan].z() = -6e-3;
  m.time = 1e-6;
  crossings.update(m);
  CHECK(crossings.plates()[0].t_contact < 0);
  m.nodes.x[live].z() = -6e-3;
  m.time = 2e-6;
  crossings.update(m);
  CHECK(crossings.plates()[0].t_contact == 2e-6);
}

TEST_CASE("each projectile is measured and named, and behind a lone plate a projectile length on",
          "[unit][analysis]") {
  // Reference: plate_crossings.hpp: each projectile has its own v_k, in scene order; the
  // measuring plane lies a clear gap behind the rear face, and with no second plate to make a
  // gap, the projectile's length along its flight. One plate 2 mm thick, front at z = -5 mm;
  // the shot (6 mm long, 1000 m/s) and a decoy projectile beside it (12 mm, 500 m/s): the
  // shot's plane is 2 + 6 = 8 mm behind the front face, the decoy's 2 + 12 = 14 mm.
  std::string text = kScene;
  const std::size_t second = text.find("[[bodies]]\nname = \"second\"");
  const std::size_t first = text.find("[[bodies]]\nname = \"first\"");
  REQUIRE(second != std::string::npos);
  REQUIRE(first != std::string::npos);
  text.erase(second, first - second);
  const std::string decoy = R"([[bodies]]
name = "decoy"
material = "steel_4340"
projectile = true
velocity = [0, 0, -500]
position = [-60e-3, 0, 1e-3]
[bodies.shape]
type = "projectile"
diameter = 4e-3
length = 12e-3
mesh_size = 3e-3
)";
  {  // the decoy listed first comes first, named so (12 mm long: plane 14 mm on)
    const std::size_t bodies = text.find("[[bodies]]");
    const Scene sc = crossingsScene("fesph_crossings_decoy_first",
                                    text.substr(0, bodies) + decoy + text.substr(bodies));
    const Model m = buildModel(sc);
    const std::vector<PlateCrossings> all = allPlateCrossings(sc, m);
    REQUIRE(all.size() == 2);
    CHECK(all[0].projectileName() == "decoy");
    CHECK(m.bodies[all[0].projectile()].name == "decoy");
    CHECK(all[1].projectileName() == "shot");
    REQUIRE(all[0].plates().size() == 1);
    CHECK(all[0].plates()[0].measure_depth == Approx(14e-3).epsilon(1e-12));
    REQUIRE(all[1].plates().size() == 1);
    CHECK(all[1].plates()[0].measure_depth == Approx(8e-3).epsilon(1e-12));
    // a body that is no projectile is not tracked
    const PlateCrossings plate(sc, m, 2);
    REQUIRE(m.bodies[2].name == "first");
    CHECK(plate.projectile() == -1);
    CHECK(plate.plates().empty());
  }
  {  // a projectile of a plate's shape (a flyer plate) is no target of the other one
    std::string flyer = decoy;
    const std::size_t shape = flyer.find("type = \"projectile\"");
    flyer.replace(shape, flyer.size() - shape,
                  "type = \"plate\"\nsize_x = 6e-3\nsize_y = 6e-3\nthickness = 2e-3\n"
                  "mesh_size = 3e-3\ncoarse_size = 3e-3\n");
    const Scene sc = crossingsScene("fesph_crossings_flyer", text + flyer);
    const Model m = buildModel(sc);
    const std::vector<PlateCrossings> all = allPlateCrossings(sc, m);
    REQUIRE(all.size() == 2);
    REQUIRE(all[0].plates().size() == 1);
    CHECK(all[0].plates()[0].name == "first");
  }
  text += decoy;
  const Scene sc = crossingsScene("fesph_crossings_lone", text);
  Model m = buildModel(sc);
  REQUIRE(m.bodies.size() == 3);
  REQUIRE(m.bodies[2].is_projectile);
  PlateCrossings crossings(sc, m, 0);
  CHECK(crossings.projectileName() == "shot");
  REQUIRE(crossings.plates().size() == 1);
  CHECK(crossings.plates()[0].measure_depth == Approx(8e-3).epsilon(1e-12));
  // the shot's nose (1 mm) moved to -13.5 mm, tail at -7.5 mm, past the rear face (-7 mm)
  for (std::size_t a = m.bodies[0].node_begin; a < m.bodies[0].node_end; ++a)
    m.nodes.x[a].z() -= 14.5e-3;
  m.time = 15e-6;
  crossings.update(m);
  CHECK(crossings.plates()[0].t_measured == 15e-6);
  CHECK(crossings.plates()[0].speed == Approx(1000.0).epsilon(1e-12));
}

TEST_CASE("v_k is the largest piece's, taken when it reaches the measuring plane, and "
          "'through' counts what is past the rear face", "[unit][analysis]") {
  // Reference: the definitions in plate_crossings.hpp. The shot of the scene above is cut in
  // two by converting a band of its elements: a small nose piece and a larger tail piece,
  // with the band's particles between. Placed by hand (no steps), for the first plate (front
  // z = -5 mm, rear -7 mm, measuring plane -15 mm):
  // 1. only the nose piece past the measuring plane: nothing is measured (a fragment ahead
  //    is not the projectile);
  // 2. the tail piece past it too, the particles inside the plate (z = -6 mm): v_1 is the tail
  //    piece's velocity, its mass fraction the tail's, and the material through the plate is
  //    the two pieces' (past the rear face), not the particles'.
  const Scene sc = crossingsScene("fesph_crossings_pieces");
  Model m = buildModel(sc);
  PlateCrossings crossings(sc, m, 0);
  m.controls.conversion.mode = ConversionMode::Sph;
  const int shot = 0;
  const Body& b = m.bodies[shot];
  for (std::size_t e = b.elem_begin; e < b.elem_end; ++e) {
    double zc = 0;
    for (int a : m.elems.conn[e]) zc += 0.25 * m.nodes.x[a].z();
    if (zc > 2e-3 && zc < 4.5e-3) m.elems.state[e].eps_p = 1.0;
  }
  REQUIRE(convertElements(m, 1.3) > 0);
  const std::vector<Piece> pieces = bodyPieces(m, shot);
  REQUIRE(pieces.size() == 2);
  const Piece& tail = pieces[0];  // the largest
  const Piece& nose = pieces[1];
  REQUIRE(nose.centroid.z() < tail.centroid.z());
  const double m0 = bodyInitialMass(m, shot);
  const auto place = [&](const Piece& piece, double z_lead, const Vec3& v) {
    double lead = 1.0;
    for (int a : piece.nodes) lead = std::min(lead, m.nodes.x[a].z());
    for (int a : piece.nodes) m.nodes.x[a].z() += z_lead - lead, m.nodes.v[a] = v;
  };
  const Vec3 v_nose(0, 0, -1500), v_tail(0, 0, -900);

  place(nose, -16e-3, v_nose);
  place(tail, -4e-3, v_tail);
  m.time = 10e-6;
  crossings.update(m);
  CHECK(crossings.plates()[0].t_contact == 10e-6);  // any node past the front face
  CHECK(crossings.plates()[0].t_measured < 0);

  place(nose, -30e-3, v_nose);
  place(tail, -15.5e-3, v_tail);
  double m_particles = 0;
  for (std::size_t i = 0; i < m.particles.size(); ++i)
    m.particles.x[i].z() = -6e-3, m_particles += m.particles.m[i];
  REQUIRE(m_particles > 0.05 * m0);
  m.time = 12e-6;
  crossings.update(m);
  const PlateCrossing& p = crossings.plates()[0];
  CHECK(p.t_measured == 12e-6);
  CHECK(p.velocity.z() == Approx(-900.0).epsilon(1e-12));
  CHECK(p.mass_fraction == Approx(tail.mass / m0).epsilon(1e-12));
  const double through = (tail.mass + nose.mass) / m0;
  CHECK(p.through_mass_fraction == Approx(through).epsilon(1e-12));
  CHECK(p.through_velocity.z() ==
        Approx(-(900 * tail.mass + 1500 * nose.mass) / (tail.mass + nose.mass)).epsilon(1e-12));
}

TEST_CASE("material past a plate counts the live nodes and the particles of the body",
          "[unit][analysis]") {
  Model m = shotWithFrontHalfConverted("fesph_crossings_past");
  const int shot = 0;
  const double m0 = bodyInitialMass(m, shot);  // from the reference volumes
  // Slow the particles to 400 m/s; the nodes keep 1000 m/s.
  const Body& b = m.bodies[shot];
  double m_particles = 0, m_nodes = 0;
  for (std::size_t i = 0; i < m.particles.size(); ++i)
    m.particles.v[i] = Vec3(0, 0, -400), m_particles += m.particles.m[i];
  for (std::size_t a = b.node_begin; a < b.node_end; ++a) m_nodes += m.nodes.m[a];
  REQUIRE(m_particles + m_nodes == Approx(m0).epsilon(1e-12));  // mass moved, not lost

  PlateCrossing plane;  // a plate whose rear face (1 mm thick) lies at z = 20 mm: all is past
  plane.front = Vec3(0, 0, 21e-3);
  const MaterialPast all = materialPast(m, plane, shot, 1e-3);
  CHECK(all.mass == Approx(m0).epsilon(1e-12));  // the plates, past it too, do not count
  CHECK(all.velocity.z() == Approx(-(1000 * m_nodes + 400 * m_particles) / m0).epsilon(1e-12));
  CHECK(all.velocity.x() == 0.0);
  // A rear face at z = -5 mm: nothing of the shot is past it yet.
  plane.front = Vec3(0, 0, -4e-3);
  CHECK(materialPast(m, plane, shot, 1e-3).mass == 0.0);
}

TEST_CASE("the body's material by region: before, in and between the plates, and beyond",
          "[unit][analysis]") {
  Model m = shotWithFrontHalfConverted("fesph_crossings_regions");
  const int shot = 0;
  const Body& b = m.bodies[shot];
  // Its particles slowed to 400 m/s and moved 3 mm off the shot line in x.
  for (std::size_t i = 0; i < m.particles.size(); ++i) {
    m.particles.v[i] = Vec3(0, 0, -400);
    m.particles.x[i].x() += 3e-3;
  }
  // Two plates across the shot: A from z = 4.5 down to 3.5 mm, B from 2.2 down to 1.6 mm.
  std::vector<PlateCrossing> plates(2);
  plates[0].name = "A", plates[0].front = Vec3(0, 0, 4.5e-3), plates[0].thickness = 1e-3;
  plates[1].name = "B", plates[1].front = Vec3(0, 0, 2.2e-3), plates[1].thickness = 0.6e-3;
  const std::vector<MaterialRegion> regions = materialByRegion(m, plates, shot);
  REQUIRE(regions.size() == 5);
  CHECK(regions[0].name == "before A");
  CHECK(regions[1].name == "in A");
  CHECK(regions[2].name == "A to B");
  CHECK(regions[3].name == "in B");
  CHECK(regions[4].name == "beyond B");
  // The same counted here along z.
  const auto regionAlongZ = [](double z) {
    return z > 4.5e-3 ? 0 : z >= 3.5e-3 ? 1 : z > 2.2e-3 ? 2 : z >= 1.6e-3 ? 3 : 4;
  };
  std::array<double, 5> nodes{}, particles{}, offset{};
  double total = 0;
  for (std::size_t a = b.node_begin; a < b.node_end; ++a)
    if (m.nodes.m[a] > 0) nodes[regionAlongZ(m.nodes.x[a].z())] += m.nodes.m[a], total += m.nodes.m[a];
  for (std::size_t i = 0; i < m.particles.size(); ++i) {
    const int r = regionAlongZ(m.particles.x[i].z());
    particles[r] += m.particles.m[i];
    offset[r] += m.particles.m[i] * std::hypot(m.particles.x[i].x(), m.particles.x[i].y());
    total += m.particles.m[i];
  }
  CHECK(total == Approx(bodyInitialMass(m, shot)).epsilon(1e-12));
  int with_particles = 0;
  for (int r = 0; r < 5; ++r) {
    CHECK(regions[r].nodes.mass == Approx(nodes[r]).epsilon(1e-12).margin(1e-18));
    CHECK(regions[r].particles.mass == Approx(particles[r]).epsilon(1e-12).margin(1e-18));
    if (particles[r] > 0) {
      ++with_particles;
      CHECK(regions[r].particles.velocity.z() == Approx(-400).epsilon(1e-12));
      CHECK(regions[r].particle_offset == Approx(offset[r] / particles[r]).epsilon(1e-12));
    }
    if (nodes[r] > 0) CHECK(regions[r].nodes.velocity.z() == Approx(-1000).epsilon(1e-12));
  }
  CHECK(with_particles >= 2);  // the converted half spans more than one region
}

TEST_CASE("a half model's velocities are the full body's: its mirror image cancels the "
          "velocity normal to the plane",
          "[unit][analysis]") {
  // A shot whose material splays out from its axis, v = (50, 200 y / R, -1000) m/s: mirror
  // symmetric about y = 0, so the full shot's mean velocity is (50, 0, -1000). Its half on
  // y >= 0 alone moves at 200 * 4 / (3 pi) = 85 m/s along +y, which the residual velocity,
  // the histories and the summary counted (the main job's v1 by ~1 m/s).
  const std::string text = std::string(R"(title = "splay"
[simulation]
end_time = 1e-6
SYMMETRY
[[bodies]]
name = "shot"
material = "steel_4340"
projectile = true
DISCRETISATION
[bodies.shape]
type = "projectile"
diameter = 8e-3
length = 8e-3
mesh_size = 1e-3
)");
  const auto model = [&](const char* folder, bool half, bool particles) {
    std::string t = text;
    t.replace(t.find("SYMMETRY"), 8, half ? "symmetry = \"half\"" : "");
    t.replace(t.find("DISCRETISATION"), 14, particles ? "discretisation = \"sph\"" : "");
    Model m = buildModel(crossingsScene(folder, t));
    const auto splay = [](const Vec3& x) { return Vec3(50, 200 * x.y() / 4e-3, -1000); };
    for (std::size_t a = 0; a < m.nodes.size(); ++a) m.nodes.v[a] = splay(m.nodes.x[a]);
    for (std::size_t i = 0; i < m.particles.size(); ++i) m.particles.v[i] = splay(m.particles.x[i]);
    return m;
  };
  const Model full = model("fesph_splay_full", false, false);
  const Model half = model("fesph_splay_half", true, false);
  const Vec3 v_full = bodyMeanVelocity(full, 0);
  CHECK(std::abs(v_full.y()) < 0.5);  // the full mesh is symmetric to its discretisation
  const Vec3 v_half = bodyMeanVelocity(half, 0);
  CHECK(v_half.y() == 0.0);
  CHECK((v_half - v_full).norm() < 0.5);
  CHECK(v_half.x() == Approx(50).epsilon(1e-12));

  // The largest piece (the whole shot) and the material past a plane: the same.
  const ResidualVelocity r = residualVelocity(half, 0);
  CHECK(r.velocity.y() == 0.0);
  CHECK(r.speed == Approx(std::hypot(50.0, 1000.0)).epsilon(1e-12));
  PlateCrossing plane;
  plane.front = Vec3(0, 0, 20e-3);
  const MaterialPast past = materialPast(half, plane, 0, 1e-3);
  REQUIRE(past.mass > 0);
  CHECK(past.velocity.y() == 0.0);
  // A part off the plane has a twin of its own in the full model: its velocity is its own.
  const Piece whole = bodyPieces(half, 0).front();
  std::vector<int> off_plane;
  Vec3 p = Vec3::Zero();
  double mass = 0;
  for (int a : whole.nodes)
    if (half.nodes.x[a].y() > 1e-3) off_plane.push_back(a), p += half.nodes.m[a] * half.nodes.v[a],
                                    mass += half.nodes.m[a];
  REQUIRE(!off_plane.empty());
  CHECK(wholeVelocity(half, off_plane, p / mass).y() == Approx(p.y() / mass).epsilon(1e-15));
  CHECK(p.y() / mass > 100);
  // A node held in every direction (a fixed rim) may lie anywhere: it does not put its part
  // on the plane.
  Model held = half;
  held.nodes.fix[off_plane[0]] = 0b111;
  CHECK(wholeVelocity(held, {off_plane[0]}, Vec3(0, 7, 0)).y() == 7.0);

  // A body of particles from the start (no nodes): its particles next to the plane say it is cut.
  const Model sph = model("fesph_splay_sph", true, true);
  REQUIRE(sph.particles.size() > 0);
  double vy = 0, m_sph = 0;
  for (std::size_t i = 0; i < sph.particles.size(); ++i)
    vy += sph.particles.m[i] * sph.particles.v[i].y(), m_sph += sph.particles.m[i];
  CHECK(vy / m_sph > 50);
  CHECK(bodyMeanVelocity(sph, 0).y() == 0.0);
  CHECK(bodyMeanVelocity(sph, 0).z() == Approx(-1000).epsilon(1e-12));
  // and its residual velocity, of its largest clump (the whole body), likewise
  const ResidualVelocity r_sph = residualVelocity(sph, 0);
  CHECK(r_sph.mass_fraction == Approx(1.0).epsilon(1e-12));
  CHECK(r_sph.velocity.y() == 0.0);
  CHECK(r_sph.speed == Approx(std::hypot(50.0, 1000.0)).epsilon(1e-12));
}
