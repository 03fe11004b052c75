// SPDX-License-Identifier: MIT
// Bodies that overlap at the start are found (and the scene refused, test_scene.cpp); bodies
// apart or touching face to face are not. Exact geometry: structured cubes whose nodes lie
// on each other's nodes and faces, the cases a strict point-in-element test gets wrong.
#include "core/mesh/structured_box.hpp"
#include "core/scene/initial_overlap.hpp"
#include "core/sph/particle_body.hpp"
#include "core/state/model_build.hpp"
#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

using namespace fesph;
using fesph::testing::elasticMaterial;

namespace {

// A unit cube (4 x 4 x 4 cells: nodes 0.25 apart) and a second body of `size` (cells of 0.25)
// at `origin`.
Model cubeAnd(const Vec3& origin, const Vec3& size = Vec3::Ones()) {
  Model m;
  m.materials.push_back(elasticMaterial());
  addBody(m, "cube", structuredBox(Vec3::Zero(), Vec3::Ones(), 4, 4, 4), 0, Placement{},
          Vec3::Zero(), false);
  const Eigen::Vector3i cells = (4 * size).array().round().cast<int>();
  addBody(m, "other", structuredBox(origin, size, cells.x(), cells.y(), cells.z()), 0,
          Placement{}, Vec3::Zero(), true);
  finaliseModel(m);
  return m;
}

}  // namespace

TEST_CASE("bodies apart or touching do not overlap", "[unit][scene]") {
  CHECK_FALSE(findInitialOverlap(cubeAnd({1.5, 0, 0})));       // apart
  CHECK_FALSE(findInitialOverlap(cubeAnd({1.0, 0, 0})));       // face to face, node on node
  CHECK_FALSE(findInitialOverlap(cubeAnd({1.0001, 0, 0})));    // apart by a hair (1e-4)
  CHECK_FALSE(findInitialOverlap(cubeAnd({1.0, 0.375, 0})));   // face to face, nodes on faces
  CHECK_FALSE(findInitialOverlap(cubeAnd({1.0, 1.0, 1.0})));   // corner to corner
  CHECK_FALSE(findInitialOverlap(cubeAnd({0, 0, -0.5}, {1, 1, 0.5})));  // below, face to face
}

TEST_CASE("a body moved into another overlaps it, nodes on nodes too", "[unit][scene]") {
  // In by one cell along x: the other's nodes at x = 0.75 with y and z in (0, 1), 3 x 3 of
  // them, lie inside the cube, each on one of its nodes (so in no element strictly); those
  // with y or z at 0 or 1, and all at x = 1, lie on its surface: touching.
  const auto one_cell = findInitialOverlap(cubeAnd({0.75, 0, 0}));
  REQUIRE(one_cell);
  CHECK(one_cell->outer == 0);
  CHECK(one_cell->inner == 1);
  CHECK(one_cell->points == 9);
  CHECK(one_cell->example.x() == Approx(0.75));

  // In by a hair: the same 9, now inside elements.
  const auto hair = findInitialOverlap(cubeAnd({0.999, 0, 0}));
  REQUIRE(hair);
  CHECK(hair->points == 9);

  // A small cube wholly inside: all its 27 nodes; the cube itself has none inside it.
  const auto inside = findInitialOverlap(cubeAnd({0.25, 0.25, 0.25}, Vec3::Constant(0.5)));
  REQUIRE(inside);
  CHECK(inside->inner == 1);
  CHECK(inside->points == 27);
  CHECK(inside->example == Vec3(0.25, 0.25, 0.25));  // the first of them, its first node
}

TEST_CASE("particles of a particle body inside another body overlap it", "[unit][scene]") {
  Model m;
  m.materials.push_back(elasticMaterial());
  addBody(m, "cube", structuredBox(Vec3::Zero(), Vec3::Ones(), 4, 4, 4), 0, Placement{},
          Vec3::Zero(), false);
  addParticleBody(m, "cloud", {Vec3(0.5, 0.5, 0.9), Vec3(0.5, 0.5, 1.1), Vec3(0.5, 0.5, 1.0)},
                  {1e-3, 1e-3, 1e-3}, 0, Vec3::Zero(), true);
  finaliseModel(m);
  const auto o = findInitialOverlap(m);
  REQUIRE(o);
  CHECK(o->inner == 1);
  CHECK(o->points == 1);  // 1.1 is outside, 1.0 on the surface
  CHECK(o->example.z() == Approx(0.9));
}

TEST_CASE("a point in a non-convex body's notch, a hair off its faces, does not overlap it",
          "[unit][scene]") {
  // An L-shaped prism: the 2 x 2 x 1 box [0, 2] x [0, 2] x [0, 1] without its cell [1, 2] x
  // [1, 2] x [0, 1]. The notch lies inside the body's bounds, so only the point-in-element
  // test decides; its tolerance (1e-9 of a barycentric coordinate) is round-off, so a point
  // 1e-5 (a hundred-thousandth of an element) off a face is outside.
  const TetMesh box = structuredBox(Vec3::Zero(), Vec3(2, 2, 1), 2, 2, 1);
  TetMesh ell;
  std::vector<int> renumbered(box.nodes.size(), -1);
  for (const auto& t : box.tets) {
    Vec3 centroid = Vec3::Zero();
    for (int a : t) centroid += 0.25 * box.nodes[a];
    if (centroid.x() > 1 && centroid.y() > 1) continue;  // the notch
    std::array<int, 4> kept{};
    for (int k = 0; k < 4; ++k) {
      int& id = renumbered[t[k]];
      if (id < 0) {
        id = static_cast<int>(ell.nodes.size());
        ell.nodes.push_back(box.nodes[t[k]]);
      }
      kept[k] = id;
    }
    ell.tets.push_back(kept);
  }
  REQUIRE(ell.tets.size() == 18);
  REQUIRE(ell.nodes.size() == 16);  // 18 of the box, less the notch's outer edge

  const auto overlapWith = [&](const Vec3& p) {
    Model m;
    m.materials.push_back(elasticMaterial());
    addBody(m, "ell", ell, 0, Placement{}, Vec3::Zero(), false);
    addParticleBody(m, "speck", {p}, {1e-9}, 0, Vec3::Zero(), true);
    finaliseModel(m);
    return findInitialOverlap(m);
  };
  CHECK_FALSE(overlapWith({1.5, 1.5, 0.5}));        // the middle of the notch
  CHECK_FALSE(overlapWith({1.5, 1.0 + 1e-5, 0.3}));  // a hair off the face y = 1
  CHECK_FALSE(overlapWith({1.0 + 1e-5, 1.5, 0.7}));  // a hair off the face x = 1
  CHECK_FALSE(overlapWith({1.5, 1.0, 0.3}));        // on the face: touching
  // and a hair inside those faces, in the body: overlaps
  const auto in_y = overlapWith({1.5, 1.0 - 1e-5, 0.3});
  REQUIRE(in_y);
  CHECK(in_y->points == 1);
  CHECK(overlapWith({1.0 - 1e-5, 1.5, 0.7}));
}
