// SPDX-License-Identifier: MIT
// Exterior surfaces: face counts of a structured box, orientation, closedness and the
// incremental update against a brute-force recount after deleting elements.
#include "core/common/error.hpp"
#include "core/contact/surfaces.hpp"
#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

#include <algorithm>
#include <map>
#include <random>
#include <set>

using namespace fesph;

namespace {

using Key = std::array<int, 3>;

Key sorted(std::array<int, 3> k) {
  std::sort(k.begin(), k.end());
  return k;
}

// Reference: (sorted face, owner) for every face of exactly one live element.
std::set<std::pair<Key, int>> bruteForceExterior(const Model& m) {
  std::map<Key, std::vector<int>> live_owners;
  for (std::size_t e = 0; e < m.elems.size(); ++e)
    if (m.elems.status[e] == ElemStatus::Live)
      for (int k = 0; k < 4; ++k)
        live_owners[sorted(tetFace(m.elems.conn[e], k))].push_back(static_cast<int>(e));
  std::set<std::pair<Key, int>> out;
  for (const auto& [key, owners] : live_owners)
    if (owners.size() == 1) out.insert({key, owners[0]});
  return out;
}

Vec3 centroid(const Model& m, const std::array<int, 4>& c) {
  return 0.25 * (m.nodes.x[c[0]] + m.nodes.x[c[1]] + m.nodes.x[c[2]] + m.nodes.x[c[3]]);
}

// Every property the surfaces must have, each checked independently of how they were built.
void checkSurfaces(const Model& m) {
  const Surfaces& s = m.surfaces;
  // 1. exactly the faces with one live element, each owned by that element
  std::set<std::pair<Key, int>> got;
  for (const ExteriorFace& f : s.exterior) got.insert({sorted(f.node), f.elem});
  REQUIRE(got.size() == s.exterior.size());  // no face twice
  REQUIRE(got == bruteForceExterior(m));

  std::map<std::pair<int, int>, int> directed_edges;
  double volume_from_surface = 0;
  std::vector<std::set<int>> nodes_of_body(m.bodies.size());
  for (std::size_t i = 0; i < s.exterior.size(); ++i) {
    const ExteriorFace& f = s.exterior[i];
    // 2. table links and body
    REQUIRE(s.table[f.face].exterior == static_cast<int>(i));
    REQUIRE(sorted(f.node) == s.table[f.face].key);
    REQUIRE(f.body == m.elems.body[f.elem]);
    // 3. outward: the normal points away from the survivor's centroid
    const Vec3 &a = m.nodes.x[f.node[0]], &b = m.nodes.x[f.node[1]], &c = m.nodes.x[f.node[2]];
    const Vec3 N = (b - a).cross(c - a);  // twice the area times the unit normal
    REQUIRE(N.dot((a + b + c) / 3.0 - centroid(m, m.elems.conn[f.elem])) > 0);
    volume_from_surface += ((a + b + c) / 3.0).dot(N) / 6.0;
    for (int k = 0; k < 3; ++k) ++directed_edges[{f.node[k], f.node[(k + 1) % 3]}];
    for (int a_id : f.node) nodes_of_body[f.body].insert(a_id);
  }
  // 4. closed and consistently oriented: every directed edge is matched by its reverse
  for (const auto& [edge, count] : directed_edges) {
    const auto it = directed_edges.find({edge.second, edge.first});
    REQUIRE(it != directed_edges.end());
    REQUIRE(it->second == count);
  }
  // 5. divergence theorem: the surface encloses exactly the live volume
  double live_volume = 0;
  for (std::size_t e = 0; e < m.elems.size(); ++e)
    if (m.elems.status[e] == ElemStatus::Live) live_volume += m.elems.V0[e];
  REQUIRE(volume_from_surface == Approx(live_volume).epsilon(1e-12).margin(1e-24));
  // 6. slave nodes: the nodes of each body's exterior faces, each once
  for (std::size_t b = 0; b < m.bodies.size(); ++b) {
    const std::vector<int>& list = s.slave_nodes[b];
    REQUIRE(std::set<int>(list.begin(), list.end()) == nodes_of_body[b]);
    REQUIRE(list.size() == nodes_of_body[b].size());
    for (std::size_t i = 0; i < list.size(); ++i)
      REQUIRE(s.node_slot[list[i]] == static_cast<int>(i));
  }
}

Model twoBoxes() {
  Model m;
  m.materials.push_back(fesph::testing::elasticMaterial());
  addBody(m, "a", structuredBox(Vec3::Zero(), Vec3(2e-3, 3e-3, 4e-3), 2, 3, 4), 0, Placement{},
          Vec3::Zero(), false);
  Placement p;
  p.translation = Vec3(5e-3, 0, 0);
  addBody(m, "b", structuredBox(Vec3::Zero(), Vec3(3e-3, 3e-3, 3e-3), 3, 3, 3), 0, p,
          Vec3::Zero(), false);
  finaliseModel(m);
  buildSurfaces(m);
  return m;
}

}  // namespace

TEST_CASE("surfaces of a structured box: the 2 triangles of every side square",
          "[unit][contact]") {
  // Reference: a box of nx*ny*nz cubes, 6 tets each, has 4 (nx ny + ny nz + nz nx) boundary
  // triangles and (4 * 6 nx ny nz + boundary) / 2 faces. Exact counts.
  Model m = fesph::testing::boxModel(fesph::testing::elasticMaterial(), Vec3(2e-3, 3e-3, 4e-3),
                                     2, 3, 4);
  buildSurfaces(m);
  REQUIRE(m.surfaces.exterior.size() == 4 * (6 + 12 + 8));
  REQUIRE(m.surfaces.table.size() == (4 * 6 * 24 + 104) / 2);
  REQUIRE(m.surfaces.slave_nodes[0].size() == 3 * 4 * 5 - 1 * 2 * 3);  // all but interior nodes
  checkSurfaces(m);
}

TEST_CASE("surfaces follow element deletion exactly", "[unit][contact]") {
  // Reference: brute-force recount of the faces with one live element after every deletion,
  // plus orientation, closedness and enclosed volume (relative 1e-12).
  Model m = twoBoxes();
  checkSurfaces(m);
  std::vector<std::size_t> order(m.elems.size());
  for (std::size_t e = 0; e < order.size(); ++e) order[e] = e;
  std::mt19937 rng(7);
  std::shuffle(order.begin(), order.end(), rng);
  for (std::size_t i = 0; i < order.size() * 3 / 4; ++i) {
    const std::size_t e = order[i];
    m.elems.status[e] = i % 2 ? ElemStatus::Eroded : ElemStatus::Converted;
    removeElementFromSurfaces(m, e);
    checkSurfaces(m);
    // a second call for the same element changes nothing, not even the faces' order
    const Surfaces before = m.surfaces;
    removeElementFromSurfaces(m, e);
    REQUIRE(m.surfaces.exterior.size() == before.exterior.size());
    for (std::size_t k = 0; k < before.exterior.size(); ++k) {
      REQUIRE(m.surfaces.exterior[k].face == before.exterior[k].face);
      REQUIRE(m.surfaces.exterior[k].elem == before.exterior[k].elem);
    }
    REQUIRE(m.surfaces.slave_nodes == before.slave_nodes);
    REQUIRE(m.surfaces.node_face_count == before.node_face_count);
  }
  // the incremental result is a rebuild's, up to order
  std::set<std::pair<Key, int>> incremental;
  for (const ExteriorFace& f : m.surfaces.exterior) incremental.insert({sorted(f.node), f.elem});
  buildSurfaces(m);
  std::set<std::pair<Key, int>> rebuilt;
  for (const ExteriorFace& f : m.surfaces.exterior) rebuilt.insert({sorted(f.node), f.elem});
  REQUIRE(incremental == rebuilt);
}

TEST_CASE("findFace finds a face from its nodes in any order", "[unit][contact]") {
  Model m = twoBoxes();
  const ExteriorFace f = m.surfaces.exterior[5];
  REQUIRE(findFace(m.surfaces, f.node[2], f.node[0], f.node[1]) == f.face);
  const auto& c = m.elems.conn[0];
  const int f0 = findFace(m.surfaces, c[1], c[3], c[2]);
  REQUIRE(f0 >= 0);
  REQUIRE(m.surfaces.elem_faces[0][0] == f0);
  // nodes of two bodies never share a face
  REQUIRE(findFace(m.surfaces, 0, 1, static_cast<int>(m.bodies[1].node_begin)) == -1);
}

TEST_CASE("a face shared by three tetrahedra is refused", "[unit][contact]") {
  Model m;
  m.bodies.push_back(Body{});
  m.nodes.body.assign(6, 0);
  m.nodes.x.assign(6, Vec3::Zero());
  m.elems.conn = {{0, 1, 2, 3}, {0, 2, 1, 4}, {0, 1, 2, 5}};
  m.elems.body.assign(3, 0);
  m.elems.status.assign(3, ElemStatus::Live);
  REQUIRE_THROWS_AS(buildSurfaces(m), InputError);
}
