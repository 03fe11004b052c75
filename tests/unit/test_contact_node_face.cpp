// SPDX-License-Identifier: MIT
// One node against one face: the Johnson-Stryk correction closes the predicted penetration,
// conserves momentum, books the energy, never pulls, ignores nodes that came through
// elsewhere, and caps friction at mu |dv_n|.
#include "core/contact/node_face_contact.hpp"
#include "core/contact/surfaces.hpp"
#include "core/solver/boundary.hpp"
#include "core/solver/step.hpp"
#include "core/sph/particle_body.hpp"
#include "core/state/model_build.hpp"
#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <stdexcept>

using namespace fesph;

namespace {

constexpr double kSize = 1e-3;  // cube edge, m
constexpr double kDt = 2e-6;    // s

// Body 0: a 1 mm cube (one cell, 6 tets) at rest, top at z = 1 mm. Body 1: a slender tet,
// 1 mm tall, standing on its apex at (ax, ay, az), moving with v.
Model apexOverCube(double ax, double ay, double az, const Vec3& v) {
  Model m;
  m.materials.push_back(fesph::testing::elasticMaterial());
  addBody(m, "cube", structuredBox(Vec3::Zero(), Vec3::Constant(kSize), 1, 1, 1), 0,
          Placement{}, Vec3::Zero(), false);
  TetMesh tet;
  const Vec3 apex(ax, ay, az);
  tet.nodes = {apex, apex + Vec3(-0.2e-3, -0.2e-3, 1e-3), apex + Vec3(0.2e-3, -0.1e-3, 1e-3),
               apex + Vec3(0, 0.2e-3, 1e-3)};
  tet.tets = {{0, 1, 2, 3}};
  if (tetVolume(tet.nodes[0], tet.nodes[1], tet.nodes[2], tet.nodes[3]) < 0)
    tet.tets = {{0, 1, 3, 2}};
  addBody(m, "tet", tet, 0, Placement{}, v, true);
  finaliseModel(m);
  buildSurfaces(m);
  return m;
}

int apexNode(const Model& m) { return static_cast<int>(m.bodies[1].node_begin); }

Vec3 momentum(const Model& m) {
  Vec3 p = Vec3::Zero();
  for (std::size_t a = 0; a < m.nodes.size(); ++a) p += m.nodes.m[a] * m.nodes.v[a];
  return p;
}

double kinetic(const Model& m) {
  double k = 0;
  for (std::size_t a = 0; a < m.nodes.size(); ++a)
    k += 0.5 * m.nodes.m[a] * m.nodes.v[a].squaredNorm();
  return k;
}

// Predicted height and velocity of the cube's top surface at (x, y): linear interpolation
// on the top triangle over that point, all at the predicted positions x + dt v.
struct TopPoint {
  double z = 0;
  Vec3 v = Vec3::Zero();
};
TopPoint topAt(const Model& m, double x, double y) {
  const Nodes& nd = m.nodes;
  for (const ExteriorFace& f : m.surfaces.exterior) {
    if (f.body != 0) continue;
    const Vec3 a = nd.x[f.node[0]] + kDt * nd.v[f.node[0]];
    const Vec3 b = nd.x[f.node[1]] + kDt * nd.v[f.node[1]];
    const Vec3 c = nd.x[f.node[2]] + kDt * nd.v[f.node[2]];
    if (std::min({a.z(), b.z(), c.z()}) < 0.5 * kSize) continue;
    const double det = (b.x() - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (b.y() - a.y());
    const double l1 = ((x - a.x()) * (c.y() - a.y()) - (c.x() - a.x()) * (y - a.y())) / det;
    const double l2 = ((b.x() - a.x()) * (y - a.y()) - (x - a.x()) * (b.y() - a.y())) / det;
    const double l0 = 1 - l1 - l2;
    if (std::min({l0, l1, l2}) < 0) continue;
    TopPoint p;
    p.z = l0 * a.z() + l1 * b.z() + l2 * c.z();
    p.v = l0 * nd.v[f.node[0]] + l1 * nd.v[f.node[1]] + l2 * nd.v[f.node[2]];
    return p;
  }
  throw std::logic_error("no top face there");
}

// Predicted gap of the apex to the cube's top surface, m (negative: penetration).
double predictedGap(const Model& m) {
  const Vec3 y = m.nodes.x[apexNode(m)] + kDt * m.nodes.v[apexNode(m)];
  return y.z() - topAt(m, y.x(), y.y()).z;
}

}  // namespace

TEST_CASE("node-face contact closes the predicted penetration and conserves momentum",
          "[unit][contact]") {
  // Reference: Johnson & Stryk (2001) / paper eqs. 1-4: after the last (alpha = 1) pass the
  // predicted penetration (initially 10 um) is gone to second order (< 1e-3 of it); momentum
  // unchanged to round-off (1e-14 relative); the kinetic energy lost is booked (1e-12).
  Model m = apexOverCube(0.4e-3, 0.3e-3, 1.01e-3, Vec3(0, 0, -10));
  const double gap0 = predictedGap(m);
  REQUIRE(gap0 == Approx(-10e-6).epsilon(1e-6));
  const Vec3 p0 = momentum(m);
  const double k0 = kinetic(m);
  for (int passes : {1, 3}) {
    Model c = m;
    c.v_node_free = c.nodes.v;
    c.v_particle_free = c.particles.v;
    enforceNodeFaceContact(c, kDt, ContactControls{passes, 0.0});
    const double dissipated = -correctionWork(c, kDt);  // no forces here: v^{n-1/2} = v
    INFO("passes " << passes << ": predicted gap " << predictedGap(c) << " m");
    REQUIRE(std::abs(predictedGap(c)) < (passes == 1 ? 1e-9 : 1e-3) * std::abs(gap0));
    REQUIRE((momentum(c) - p0).norm() < 1e-14 * p0.norm());
    REQUIRE(dissipated > 0);
    REQUIRE(dissipated == Approx(k0 - kinetic(c)).epsilon(1e-12));
    REQUIRE(c.nodes.v[apexNode(c)].z() > -10.0);
    // one pass: all along the face normal (z); more passes: the pushed face tilts a little
    if (passes == 1)
      for (std::size_t a = 0; a < c.nodes.size(); ++a)
        REQUIRE(std::abs(c.nodes.v[a].x()) + std::abs(c.nodes.v[a].y()) < 1e-12);
  }
}

TEST_CASE("node-face contact never pulls and ignores nodes outside the face",
          "[unit][contact]") {
  // Reference: no penetration predicted -> velocities unchanged bit for bit.
  for (const Model& m : {apexOverCube(0.4e-3, 0.3e-3, 1.01e-3, Vec3(0, 0, +10)),   // leaving
                         apexOverCube(0.4e-3, 0.3e-3, 1.03e-3, Vec3(0, 0, -10)),   // short of it
                         apexOverCube(1.3e-3, 0.3e-3, 1.01e-3, Vec3(0, 0, -10))})  // beside it
  {
    Model c = m;
    enforceNodeFaceContact(c, kDt, ContactControls{});
    REQUIRE(c.nodes.v == m.nodes.v);
  }
}

TEST_CASE("a node that starts deep behind a face is not snapped through it", "[unit][contact]") {
  // Reference: the apex starts 0.5 mm inside the cube (0.35 of the longest edge of every
  // cube face from it): it did not cross any of them, so with the default depth tolerance
  // (0.2) nothing moves; with tolerance 0.6 the nearest side face would take it (the check
  // bites).
  const Model m = apexOverCube(0.4e-3, 0.3e-3, 0.5e-3, Vec3(0, 0, -10));
  Model c = m;
  enforceNodeFaceContact(c, kDt, ContactControls{});
  REQUIRE(c.nodes.v == m.nodes.v);
  ContactControls loose;
  loose.depth_tolerance = 0.6;
  enforceNodeFaceContact(c, kDt, loose);
  REQUIRE(c.nodes.v[apexNode(c)] != m.nodes.v[apexNode(m)]);
}

TEST_CASE("a node crossing the top face by a cube's edge is held by the top, not the side",
          "[unit][contact]") {
  // Reference: the face a node moves into fastest is the one it crosses. The apex, 18 um
  // above the top and 10 um inside the side x = 1 mm, moves by (-10, 0, -20) um in the step:
  // it crosses the top (approach 20 um, predicted depth 2 um), and only grazes the side's
  // plane (approach 10 um, depth 10 um from where it started). One pass (alpha = 1) must
  // close the top's penetration along z alone: the x velocity keeps its bits.
  const Model m = apexOverCube(0.99e-3, 0.5e-3, 1.018e-3, Vec3(-5, 0, -10));
  const double gap0 = predictedGap(m);
  REQUIRE(gap0 == Approx(-2e-6).epsilon(1e-6));
  Model c = m;
  enforceNodeFaceContact(c, kDt, ContactControls{1, 0.0});
  CHECK(c.nodes.v[apexNode(c)].x() == -5.0);
  CHECK(std::abs(predictedGap(c)) < 1e-9 * std::abs(gap0));
}

TEST_CASE("a node deep behind a tilted face, inside its box, is not snapped through it",
          "[unit][contact]") {
  // Reference: as above, turned 50 degrees about (1, 1, 0): the cube's faces lie oblique to
  // the axes, so the broad phase's axis-aligned boxes (widened by 0.2 of the longest edge)
  // hold the apex, 0.5 mm inside the cube, and only the narrow phase's test of the side the
  // node started on (more than the tolerance behind every face) keeps it where it is.
  Model m = apexOverCube(0.4e-3, 0.3e-3, 0.5e-3, Vec3(0, 0, -10));
  const Eigen::Matrix3d R = Eigen::AngleAxisd(50.0 * M_PI / 180.0, Vec3(1, 1, 0).normalized())
                                .toRotationMatrix();
  for (std::size_t a = 0; a < m.nodes.size(); ++a) {
    m.nodes.x[a] = R * m.nodes.x[a];
    m.nodes.x0[a] = R * m.nodes.x0[a];
    m.nodes.v[a] = R * m.nodes.v[a];
  }
  buildSurfaces(m);
  Model c = m;
  enforceNodeFaceContact(c, kDt, ContactControls{});
  REQUIRE(c.nodes.v == m.nodes.v);
}

TEST_CASE("held master nodes stop a node alone", "[unit][contact]") {
  // Reference: a fully fixed face has infinite mass: the apex alone takes the correction
  // (its predicted position lands on the face, 1e-12 relative) and the face stays at rest.
  Model m = apexOverCube(0.4e-3, 0.3e-3, 1.01e-3, Vec3(0, 0, -10));
  for (std::size_t a = m.bodies[0].node_begin; a < m.bodies[0].node_end; ++a) m.nodes.fix[a] = 7;
  enforceNodeFaceContact(m, kDt, ContactControls{});
  REQUIRE(std::abs(predictedGap(m)) < 1e-12 * kSize);
  for (std::size_t a = m.bodies[0].node_begin; a < m.bodies[0].node_end; ++a)
    REQUIRE(m.nodes.v[a] == Vec3::Zero());
}

TEST_CASE("Coulomb friction: capped by mu |dv_n|, never reverses sliding", "[unit][contact]") {
  // Reference: Coulomb's law on the impulses (one pass: the face normal stays z). mu = 0:
  // tangential velocities unchanged (1e-12); mu = 0.1: the apex loses exactly mu |dv_n| of
  // its sliding speed (1e-9); mu = 10, three passes: sliding relative to the face stops
  // without reversing (|relative x velocity| < 1e-3 of 20 m/s: the pushed face tilts by
  // ~1e-2, so x is not exactly tangential).
  const Model m = apexOverCube(0.4e-3, 0.3e-3, 1.01e-3, Vec3(20, 0, -10));
  const int s = apexNode(m);
  auto relativeSliding = [&](const Model& c) {
    const Vec3 y = c.nodes.x[s] + kDt * c.nodes.v[s];
    return c.nodes.v[s].x() - topAt(c, y.x(), y.y()).v.x();
  };
  {
    Model c = m;
    enforceNodeFaceContact(c, kDt, ContactControls{1, 0.0});
    REQUIRE(c.nodes.v[s].z() > -10.0);
    REQUIRE(std::abs(c.nodes.v[s].x() - 20.0) < 1e-12 * 20.0);
  }
  {
    Model c = m;
    enforceNodeFaceContact(c, kDt, ContactControls{1, 0.1});
    const double dvn = c.nodes.v[s].z() - m.nodes.v[s].z();
    const double dvt = c.nodes.v[s].x() - m.nodes.v[s].x();
    REQUIRE(dvn > 0);
    REQUIRE(dvt == Approx(-0.1 * dvn).epsilon(1e-9));
  }
  {
    Model c = m;
    enforceNodeFaceContact(c, kDt, ContactControls{3, 10.0});
    REQUIRE(c.nodes.v[s].x() < 19.0);
    REQUIRE(std::abs(relativeSliding(c)) < 1e-3 * 20.0);
  }
}

TEST_CASE("a rigid wall lands nodes on it and its friction slows or stops their sliding",
          "[unit][contact]") {
  // Reference: the wall's contract (boundary.cpp): a node that would end the step behind the
  // wall gets the normal velocity change dvn that lands it on the wall; Coulomb friction then
  // takes mu dvn off its tangential speed, at most all of it (it sticks, never slides back).
  // A 1 mm cube 0.01 mm over the wall at 200 m/s down and 50 m/s along x, dt 0.1 us: dvn =
  // 100 m/s for the bottom nodes. mu = 0: sliding kept; mu = 0.1: 50 -> 40 m/s; mu = 1:
  // stopped. To round-off (1e-12 m/s relative).
  const double dt = 1e-7, lift = 1e-5;
  for (const double mu : {0.0, 0.1, 1.0}) {
    CAPTURE(mu);
    Model m = fesph::testing::boxModel(fesph::testing::elasticMaterial(), Vec3(1e-3, 1e-3, 1e-3),
                                       1, 1, 1, Vec3(50, 0, -200));
    for (Vec3& x : m.nodes.x) x.z() += lift;
    RigidWall wall;
    wall.friction = mu;
    m.walls.push_back(wall);
    enforceRigidWalls(m, dt);
    const double slide = std::max(0.0, 50 - mu * 100);
    for (std::size_t a = 0; a < m.nodes.size(); ++a) {
      const Vec3& v = m.nodes.v[a];
      if (m.nodes.x[a].z() > 1e-4) {  // the top: untouched
        CHECK(v == Vec3(50, 0, -200));
        continue;
      }
      CHECK(m.nodes.x[a].z() + dt * v.z() == Approx(0.0).margin(1e-18));  // on the wall
      CHECK(v.x() == Approx(slide).margin(1e-12 * 50));
      CHECK(v.y() == 0.0);
    }
  }
}

TEST_CASE("a rigid wall stops particles half their spacing off it", "[unit][contact][sph]") {
  // Reference: the wall's contract for particles (boundary.cpp): a particle stands for a cube
  // of its volume, so it ends a step that would take it closer than half its spacing cbrt(V)
  // on that distance, frictionless; one already closer (born there) is only kept from coming
  // closer. Particles of 1 mm^3 (spacing 1 mm): from 0.51 mm over the wall at 200 m/s down,
  // dt 0.1 us, it lands at 0.5 mm; from 0.2 mm it stops; one moving off keeps its velocity.
  // To round-off (1e-15 m).
  const double dt = 1e-7, V = 1e-9, half = 0.5e-3;
  Model m;
  m.materials.push_back(fesph::testing::elasticMaterial());
  addParticleBody(m, "drops",
                  {Vec3(0, 0, 0.51e-3), Vec3(2e-3, 0, 0.2e-3), Vec3(4e-3, 0, 0.2e-3),
                   Vec3(6e-3, 0, 2e-3)},
                  {V, V, V, V}, 0, Vec3::Zero(), true);
  finaliseModel(m);
  const std::vector<Vec3> v0 = {Vec3(50, 0, -200), Vec3(50, 0, -200), Vec3(0, 30, 200),
                                Vec3(0, 0, -200)};
  m.particles.v = v0;
  m.walls.push_back(RigidWall{});  // z = 0, normal +z
  enforceRigidWalls(m, dt);
  const Particles& pa = m.particles;
  CHECK(pa.x[0].z() + dt * pa.v[0].z() == Approx(half).margin(1e-15));
  CHECK(pa.v[0].x() == 50.0);  // frictionless
  CHECK(pa.v[1] == Vec3(50, 0, 0));
  CHECK(pa.v[2] == v0[2]);
  CHECK(pa.v[3] == v0[3]);  // 2 mm off: 20 um down in the step, still clear
}

TEST_CASE("fixed velocity bits hold their own components only", "[unit][fem]") {
  // Reference: Nodes::fix, bit k holds velocity component k at zero (boundary.cpp); the other
  // components and the unfixed nodes keep their velocity exactly.
  Model m = fesph::testing::boxModel(fesph::testing::elasticMaterial(), Vec3(1e-3, 1e-3, 1e-3),
                                     1, 1, 1, Vec3(1, 2, 3));
  REQUIRE(m.nodes.size() == 8);
  for (std::size_t a = 0; a < 8; ++a) m.nodes.fix[a] = static_cast<std::uint8_t>(a);
  applyFixedVelocities(m);
  for (std::size_t a = 0; a < 8; ++a) {
    CAPTURE(a);
    for (int k = 0; k < 3; ++k) CHECK(m.nodes.v[a][k] == ((a >> k) & 1u ? 0.0 : k + 1.0));
  }
}
