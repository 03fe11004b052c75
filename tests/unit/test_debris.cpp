// SPDX-License-Identifier: MIT
// Clumps of free particles and their straight-line strikes on plates (core/analysis/debris).
#include "core/analysis/debris.hpp"
#include "tests/support/temp_folder.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <fstream>
#include <sstream>

using namespace fesph;

namespace {

// An n x n x n lattice of particles (spacing 2 r, radius r) from `corner`, all at velocity v.
void addLattice(std::vector<DebrisParticle>& p, const Vec3& corner, int n, double r,
                const Vec3& v, int body, double damage = 0.5) {
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        DebrisParticle q;
        q.x = corner + 2 * r * Vec3(i, j, k);
        q.v = v;
        q.mass = 1e-3;
        q.radius = r;
        q.damage = damage;
        q.body = body;
        p.push_back(q);
      }
}

}  // namespace

TEST_CASE("debris: lattices apart are separate clumps with exact sums", "[unit][analysis]") {
  // Reference: exact bookkeeping. Two lattices of 27 and 8 particles (spacing 2 r) 10 r apart,
  // and a single particle; each is one clump with the lattice's mass, centroid and velocity,
  // and the clumps' masses sum to all particles' (to round-off).
  const double r = 1e-3;
  std::vector<DebrisParticle> p;
  addLattice(p, Vec3(0, 0, 0), 3, r, Vec3(0, 0, -400), 0);
  addLattice(p, Vec3(0.014, 0, 0), 2, r, Vec3(100, 0, -300), 0, 1.0);
  addLattice(p, Vec3(0, 0.05, 0), 1, r, Vec3(0, 0, 10), 0);
  const std::vector<Clump> c = findClumps(p);
  REQUIRE(c.size() == 3);
  REQUIRE(c[0].particles == 27);
  REQUIRE(c[1].particles == 8);
  REQUIRE(c[2].particles == 1);
  REQUIRE(c[0].mass == Approx(27e-3).epsilon(1e-14));
  REQUIRE(c[0].mass + c[1].mass + c[2].mass == Approx(36e-3).epsilon(1e-14));
  REQUIRE((c[0].centroid - Vec3(2 * r, 2 * r, 2 * r)).norm() < 1e-15);
  REQUIRE((c[1].centroid - Vec3(0.014 + r, r, r)).norm() < 1e-15);
  REQUIRE((c[1].velocity - Vec3(100, 0, -300)).norm() < 1e-12);
  REQUIRE(c[1].damage == Approx(1.0).epsilon(1e-14));
  REQUIRE(c[0].spread == Approx(0.0).margin(1e-12));
  // rms distance of a 3^3 lattice of spacing 2r from its centre: 2r sqrt(3 * 2/3) = 2r sqrt(2)
  REQUIRE(c[0].size == Approx(2 * r * std::sqrt(2.0)).epsilon(1e-12));
  REQUIRE_FALSE(c[0].on_plane);
  REQUIRE(c[0].full_mass == c[0].mass);
}

TEST_CASE("debris: the link distance decides, and bodies never link", "[unit][analysis]") {
  // Reference: the definition |x_i - x_j| <= link (r_i + r_j) with link = 1.5 (3 r here).
  const double r = 1e-3;
  auto pair = [&](double gap, int body_b) {
    std::vector<DebrisParticle> p;
    addLattice(p, Vec3(0, 0, 0), 1, r, Vec3::Zero(), 0);
    addLattice(p, Vec3(gap, 0, 0), 1, r, Vec3::Zero(), body_b);
    return findClumps(p).size();
  };
  REQUIRE(pair(2.99 * r, 0) == 1);
  REQUIRE(pair(3.01 * r, 0) == 2);
  // Exactly at the link distance (the "<=" of the definition): with r a power of two the gap
  // 3 r and the reach 1.5 (r + r) are the same double, and so are their squares.
  const double r2 = std::ldexp(1.0, -10);
  std::vector<DebrisParticle> touching;
  addLattice(touching, Vec3(0, 0, 0), 1, r2, Vec3::Zero(), 0);
  addLattice(touching, Vec3(3 * r2, 0, 0), 1, r2, Vec3::Zero(), 0);
  REQUIRE(findClumps(touching).size() == 1);
  REQUIRE(pair(2.0 * r, 1) == 2);  // touching, but of different plates
  // A chain linked end to end across many grid cells is one clump.
  std::vector<DebrisParticle> chain;
  for (int i = 0; i < 40; ++i) addLattice(chain, Vec3(2.9 * r * i, 0, 0), 1, r, Vec3::Zero(), 0);
  REQUIRE(findClumps(chain).size() == 1);
  // Spread: two halves moving apart at +-50 m/s about a common velocity.
  chain.clear();
  addLattice(chain, Vec3(0, 0, 0), 1, r, Vec3(50, 0, 0), 0);
  addLattice(chain, Vec3(2 * r, 0, 0), 1, r, Vec3(-50, 0, 0), 0);
  REQUIRE(findClumps(chain).front().spread == Approx(50.0).epsilon(1e-12));
}

TEST_CASE("debris: a clump on a half model's plane stands for twice its mass",
          "[unit][analysis]") {
  // Reference: the mirror image. A lattice whose first layer lies at y = r (one radius off the
  // plane y = 0) is cut by the plane in the full model; one 10 r off it is not.
  const double r = 1e-3;
  DebrisOptions half;
  half.half = true;
  std::vector<DebrisParticle> p;
  addLattice(p, Vec3(0, r, 0), 2, r, Vec3::Zero(), 0);
  addLattice(p, Vec3(0.05, 10 * r, 0), 2, r, Vec3::Zero(), 0);
  const std::vector<Clump> c = findClumps(p, half);
  REQUIRE(c.size() == 2);
  REQUIRE(c[0].on_plane);
  REQUIRE(c[0].full_mass == Approx(2 * c[0].mass).epsilon(1e-15));
  REQUIRE_FALSE(c[1].on_plane);
  REQUIRE(findClumps(p).front().on_plane == false);  // a full model has no plane
  // With its mirror image the clump on the plane is one clump of the full model: its centre
  // on the plane, moving along it; its half's sideways 30 m/s is the full clump's spread
  // (its halves fly apart), its half's 40 m/s along x its motion. The clump off the plane has
  // a twin: its own values.
  std::vector<DebrisParticle> moving;
  addLattice(moving, Vec3(0, r, 0), 2, r, Vec3(40, 30, 0), 0);
  addLattice(moving, Vec3(0.05, 10 * r, 0), 2, r, Vec3(40, 30, 0), 0);
  const std::vector<Clump> m = findClumps(moving, half);
  REQUIRE(m[0].on_plane);
  CHECK(m[0].velocity == Vec3(40, 0, 0));
  CHECK(m[0].centroid.y() == 0.0);
  CHECK(m[0].spread == Approx(30.0).epsilon(1e-12));
  // Its size from the centre on the plane: the half's rms distance from its own centre and
  // that centre's distance from the plane, in quadrature.
  Vec3 centre = Vec3::Zero();
  double mass = 0, size2 = 0;
  for (const DebrisParticle& q : moving)
    if (q.x.y() < 5 * r) centre += q.mass * q.x, mass += q.mass;
  centre /= mass;
  for (const DebrisParticle& q : moving)
    if (q.x.y() < 5 * r) size2 += q.mass * (q.x - centre).squaredNorm() / mass;
  CHECK(m[0].size == Approx(std::hypot(std::sqrt(size2), centre.y())).epsilon(1e-12));
  CHECK(m[1].velocity == Vec3(40, 30, 0));
  CHECK(m[1].spread == Approx(0.0).margin(1e-12));
  // A particle links with its own mirror image when 2 |y| <= link (r + r), i.e. |y| <= 1.5 r:
  // a layer 1.4 r off the plane is cut by it, one 1.6 r off is not.
  for (const double y : {1.4, 1.6}) {
    std::vector<DebrisParticle> q;
    addLattice(q, Vec3(0, y * r, 0), 2, r, Vec3::Zero(), 0);
    INFO("first layer " << y << " r off the plane");
    REQUIRE(findClumps(q, half).front().on_plane == (y < 1.5));
  }
}

TEST_CASE("debris: straight-line strikes on plates", "[unit][analysis]") {
  // Reference: kinematics x(t) = c + v t. Plate A's front face at z = 0 (normal +z, 0.1 m
  // square around the origin), plate B's at z = -0.5 m.
  TargetPlate a;
  a.name = "A";
  a.body = 1;
  a.front = 0.0;
  a.half_u = a.half_v = 0.05;
  TargetPlate b = a;
  b.name = "B";
  b.body = 2;
  b.centre = Vec3(0, 0, -0.503);  // mid-plane 3 mm behind the front face
  b.front = 0.003;
  b.half_u = b.half_v = 0.5;
  const std::vector<TargetPlate> plates = {a, b};
  Clump c;
  c.body = 0;
  c.centroid = Vec3(0.01, 0, 0.2);
  c.velocity = Vec3(0, 0, -400);
  Strike s = predictStrike(c, plates);
  REQUIRE(s.plate == 0);
  REQUIRE(s.after == Approx(0.2 / 400).epsilon(1e-14));
  REQUIRE((s.point - Vec3(0.01, 0, 0)).norm() < 1e-15);
  REQUIRE(s.normal_speed == 400);
  // Its own plate is never a target: a fragment of A heads for B.
  c.body = 1;
  s = predictStrike(c, plates);
  REQUIRE(s.plate == 1);
  REQUIRE(s.after == Approx(0.7 / 400).epsilon(1e-14));
  // Oblique: 300 m/s sideways carries it 0.525 m off B's centre in x: beside the plate.
  c.velocity = Vec3(300, 0, -400);
  REQUIRE(predictStrike(c, plates).plate == -1);
  c.velocity = Vec3(200, 0, -400);  // 0.36 m: on it
  s = predictStrike(c, plates);
  REQUIRE(s.plate == 1);
  REQUIRE(s.point.x() == Approx(0.01 + 0.35).epsilon(1e-13));
  // The same sideways in y, along the plate's other in-plane axis v.
  c.velocity = Vec3(0, 300, -400);
  REQUIRE(predictStrike(c, plates).plate == -1);
  c.velocity = Vec3(0, 200, -400);
  s = predictStrike(c, plates);
  REQUIRE(s.plate == 1);
  REQUIRE(s.point.y() == Approx(0.35).epsilon(1e-13));
  // Moving away, or behind every plate: no strike.
  c.velocity = Vec3(0, 0, 400);
  REQUIRE(predictStrike(c, plates).plate == -1);
  c.velocity = Vec3(0, 0, -400);
  c.centroid = Vec3(0, 0, -0.6);
  REQUIRE(predictStrike(c, plates).plate == -1);
}

TEST_CASE("debris: the CSV lists clumps of at least two particles with their strikes",
          "[unit][analysis]") {
  const double r = 1e-3;
  std::vector<DebrisParticle> p;
  addLattice(p, Vec3(0, 0, 0.1), 2, r, Vec3(0, 0, -100), 0);
  addLattice(p, Vec3(0.02, 0, 0.1), 1, r, Vec3(0, 0, -100), 0);  // spray: not listed
  TargetPlate t;
  t.name = "plate_2";
  t.body = 1;
  t.half_u = t.half_v = 1;
  testing::TempFolder dir("debris_csv");
  const std::string path = (dir.path / "debris.csv").string();
  const DebrisSummary summary = writeDebrisCsv(path, 1e-3, findClumps(p), {t}, {"plate_1", "plate_2"});
  CHECK(summary.clumps == 1);  // the single particle is not a row
  CHECK(summary.strikes == 1);
  std::ifstream in(path);
  std::string header, row, extra;
  REQUIRE(std::getline(in, header));
  REQUIRE(std::getline(in, row));
  REQUIRE_FALSE(std::getline(in, extra));
  REQUIRE(header.rfind("time_s,body,clump,particles,mass_kg", 0) == 0);
  INFO(row);
  REQUIRE(row.rfind("0.001,plate_1,1,8,0.008,0.008,100,", 0) == 0);
  // strikes plate_2 (front face z = 0) after (0.1 + r) / 100 s
  REQUIRE(row.find(",plate_2,0.00101,0.00201,") != std::string::npos);
}

TEST_CASE("debris: the CSV numbers clumps per body, lists pairs, and names unknown bodies",
          "[unit][analysis]") {
  // Reference: the table's rules. Rows largest clump first (equal masses in the order of their
  // first particle); the clump column counts within each body; a pair is a clump of two, the
  // least the table lists by default; a body index beyond the names is written "body<index>".
  const double r = 1e-3;
  std::vector<DebrisParticle> p;
  addLattice(p, Vec3(0, 0, 0.1), 2, r, Vec3(0, 0, -100), 0);
  addLattice(p, Vec3(0.1, 0, 0.1), 1, r, Vec3(0, 0, -100), 0);  // a pair of plate_1
  addLattice(p, Vec3(0.1 + 2 * r, 0, 0.1), 1, r, Vec3(0, 0, -100), 0);
  addLattice(p, Vec3(0.2, 0, 0.1), 2, r, Vec3(0, 0, -100), 1);
  addLattice(p, Vec3(0.3, 0, 0.1), 1, r, Vec3(0, 0, -100), 7);  // a pair of body 7
  addLattice(p, Vec3(0.3 + 2 * r, 0, 0.1), 1, r, Vec3(0, 0, -100), 7);
  addLattice(p, Vec3(0.4, 0, 0.1), 1, r, Vec3(0, 0, -100), 1);  // spray: not listed
  testing::TempFolder dir("debris_ranks");
  const std::string path = (dir.path / "debris.csv").string();
  const DebrisSummary summary =
      writeDebrisCsv(path, 0.0, findClumps(p), {}, {"plate_1", "plate_2"});
  CHECK(summary.clumps == 4);
  CHECK(summary.strikes == 0);
  std::ifstream in(path);
  std::string line;
  REQUIRE(std::getline(in, line));  // the header
  std::vector<std::string> starts;
  while (std::getline(in, line)) {  // time, body, clump, particles
    std::size_t end = 0;
    for (int field = 0; field < 4; ++field) end = line.find(',', end + 1);
    starts.push_back(line.substr(0, end));
  }
  REQUIRE(starts == std::vector<std::string>{"0,plate_1,1,8", "0,plate_2,1,8", "0,plate_1,2,2",
                                             "0,body7,1,2"});
}
