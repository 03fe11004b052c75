// SPDX-License-Identifier: MIT
// Hole metrics on structured plates with holes cut along whole cube columns, so the true hole
// area (cubes x cube area) and centroid are known exactly.
#include "core/analysis/hole_metrics.hpp"

#include "core/analysis/debris.hpp"

#include "core/mesh/structured_box.hpp"
#include "tests/support/models.hpp"

#include <catch2/catch.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

using namespace fesph;

namespace {

struct Circle {
  double x, y, r;
  bool contains(double px, double py) const { return std::hypot(px - x, py - y) < r; }
};

/// Centre (mm) of the 1 mm cube column, on whole millimetres, that holds tet t's centroid.
std::pair<double, double> columnCentre(const std::vector<Vec3>& x, const std::array<int, 4>& t) {
  const Vec3 c = 0.25e3 * (x[t[0]] + x[t[1]] + x[t[2]] + x[t[3]]);
  return {std::floor(c.x()) + 0.5, std::floor(c.y()) + 0.5};
}

/// A plate of 1 mm cubes over [x0, x0 + nx mm] x [y0, y0 + ny mm] x [-nz mm, 0] (x0, y0 whole
/// mm) with the cube columns whose centre lies in one of `holes` removed. Also returns the
/// true holes: area and centroid of the removed columns (of each circle, full plate when
/// `mirror_y`).
struct HolePlate {
  TetMesh mesh;
  std::vector<std::array<int, 4>> live;
  std::vector<bool> eroded;  ///< per tet
  std::vector<double> true_area;
  std::vector<Vec3> true_centroid;
};

HolePlate holePlate(double x0, double y0, int nx, int ny, int nz, const std::vector<Circle>& holes,
                    bool mirror_y = false) {
  const double mm = 1e-3;
  HolePlate p;
  p.mesh = structuredBox(Vec3(x0 * mm, y0 * mm, -nz * mm), Vec3(nx * mm, ny * mm, nz * mm), nx,
                         ny, nz);
  for (const auto& t : p.mesh.tets) {
    const auto [cx, cy] = columnCentre(p.mesh.nodes, t);
    bool gone = false;
    for (const Circle& h : holes) gone |= h.contains(cx, cy);
    p.eroded.push_back(gone);
    if (!gone) p.live.push_back(t);
  }
  for (const Circle& h : holes) {
    double n = 0, sx = 0, sy = 0;
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const double cx = x0 + i + 0.5, cy = y0 + j + 0.5;
        if (!h.contains(cx, cy)) continue;
        const double w = mirror_y ? 2.0 : 1.0;  // the mirror image has the same area
        n += w;
        sx += w * cx;
        sy += mirror_y ? 0.0 : cy;
      }
    p.true_area.push_back(n * mm * mm);
    p.true_centroid.push_back(Vec3(sx / n * mm, sy / n * mm, -0.5 * nz * mm));
  }
  return p;
}

/// The area a closed outline encloses (shoelace in x, y; the plates here face +z).
double enclosedArea(const std::vector<Vec3>& outline) {
  double area2 = 0;
  for (std::size_t k = 0; k < outline.size(); ++k) {
    const Vec3& a = outline[k];
    const Vec3& b = outline[(k + 1) % outline.size()];
    area2 += a.x() * b.y() - a.y() * b.x();
  }
  return 0.5 * std::abs(area2);
}

/// The tets of a 40 x 40 x 2 mm plate of 1 mm cubes whose cube column `keep` takes (column
/// centre in mm).
std::vector<std::array<int, 4>> columnsKept(const TetMesh& mesh,
                                            bool (*keep)(double cx, double cy)) {
  std::vector<std::array<int, 4>> live;
  for (const auto& t : mesh.tets) {
    const auto [cx, cy] = columnCentre(mesh.nodes, t);
    if (keep(cx, cy)) live.push_back(t);
  }
  return live;
}


/// The plate as a body made of particles (discretisation = "sph"): one particle per live tet,
/// at its centroid, of its volume (radius half the volume's cube root, as the solver's) in
/// steel. `plug_shift`: the removed tets' particles too, moved by it (a plug pushed out).
std::vector<DebrisParticle> particlesOf(const HolePlate& p, const Vec3* plug_shift = nullptr) {
  std::vector<DebrisParticle> out;
  for (std::size_t t = 0; t < p.mesh.tets.size(); ++t) {
    if (p.eroded[t] && !plug_shift) continue;
    const auto& n = p.mesh.tets[t];
    const std::vector<Vec3>& x = p.mesh.nodes;
    DebrisParticle q;
    q.x = 0.25 * (x[n[0]] + x[n[1]] + x[n[2]] + x[n[3]]);
    if (p.eroded[t]) q.x += *plug_shift;
    const double V = std::abs((x[n[1]] - x[n[0]]).dot((x[n[2]] - x[n[0]]).cross(x[n[3]] - x[n[0]]))) / 6;
    q.radius = 0.5 * std::cbrt(V);
    q.mass = 7850 * V;
    q.body = 0;
    out.push_back(q);
  }
  return out;
}
}  // namespace

TEST_CASE("hole metrics: two holes of known size", "[unit][analysis]") {
  // 60 x 40 x 3 mm plate; a 16 mm and an 8 mm hole.
  const HolePlate p = holePlate(-30, -20, 60, 40, 3, {{-15, 0, 8}, {15, 5, 4}});
  const PlateHoles h = findHoles(p.mesh.nodes, p.live);
  REQUIRE(h.holes.size() == 2);
  CHECK(h.normal.z() == Approx(1.0).margin(1e-9));
  for (int k = 0; k < 2; ++k) {
    CHECK(h.holes[k].area == Approx(p.true_area[k]).epsilon(0.02));
    CHECK(h.holes[k].diameter == Approx(std::sqrt(4 * p.true_area[k] / M_PI)).epsilon(0.01));
    CHECK((h.holes[k].centroid - p.true_centroid[k]).norm() < 0.1e-3);
    CHECK_FALSE(h.holes[k].on_symmetry);
    // the outline runs around the hole, at about its radius from the centroid
    const double r = std::sqrt(p.true_area[k] / M_PI);
    REQUIRE(h.holes[k].outline.size() > 8);
    for (const Vec3& q : h.holes[k].outline)
      CHECK((q - h.holes[k].centroid).norm() == Approx(r).margin(1.0e-3));
    // a loop of cell edges with its corners cut by half a cell: the cells' area less half a
    // cell (see "a hole wrapped round a piece held at its corners"), to 1e-9
    CHECK(enclosedArea(h.holes[k].outline) ==
          Approx(h.holes[k].area - 0.5 * h.cell_size * h.cell_size).epsilon(1e-9));
  }
  CHECK(h.front - h.rear == Approx(3e-3));
  // the default cell: a quarter of the 10th-percentile tet edge (1 mm here: the cubes' edges)
  CHECK(h.cell_size == Approx(0.25e-3).epsilon(1e-12));
}

TEST_CASE("hole metrics: a plate facing any way gets its frame and its hole", "[unit][analysis]") {
  // Reference: PlateHoles (hole_metrics.hpp): the normal is the direction of the plate's
  // smallest extent with its largest component positive, u and v complete a right-handed
  // frame with v along global y where the plate allows it. The plate of the first test turned
  // to face +x, +y, +z and 25 degrees off +z about y (the oblique scene's plates): the same
  // two holes, the same areas (2 %), the frame orthonormal to 1e-12.
  const HolePlate p = holePlate(-30, -20, 60, 40, 3, {{-15, 0, 8}, {15, 5, 4}});
  const double tilt = 25.0 * M_PI / 180.0;
  const std::vector<Mat3> turns = {
      Eigen::AngleAxisd(M_PI / 2, Vec3::UnitY()).toRotationMatrix(),   // z to +x
      Eigen::AngleAxisd(-M_PI / 2, Vec3::UnitX()).toRotationMatrix(),  // z to +y
      Mat3::Identity(), Eigen::AngleAxisd(tilt, Vec3::UnitY()).toRotationMatrix()};
  for (const Mat3& R : turns) {
    const Vec3 facing = R * Vec3::UnitZ();
    CAPTURE(facing.transpose());
    std::vector<Vec3> x = p.mesh.nodes;
    for (Vec3& q : x) q = R * q;
    // found from the nodes, and given (exactly: +y then has no in-plane part of global y)
    HoleOptions given;
    given.normal = facing.unaryExpr([](double c) { return std::abs(c) < 1e-15 ? 0.0 : c; });
    for (const PlateHoles& h : {findHoles(x, p.live), findHoles(x, p.live, given)}) {
      CHECK((h.normal - facing).norm() < 1e-9);
      CHECK(std::abs(h.u.norm() - 1) < 1e-12);
      CHECK(std::abs(h.v.norm() - 1) < 1e-12);
      CHECK(std::abs(h.u.dot(h.v)) < 1e-12);
      CHECK((h.u.cross(h.v) - h.normal).norm() < 1e-12);
      REQUIRE(h.holes.size() == 2);
      for (int k = 0; k < 2; ++k) {
        CHECK(h.holes[k].area == Approx(p.true_area[k]).epsilon(0.02));
        CHECK((h.holes[k].centroid - R * p.true_centroid[k]).norm() < 0.1e-3);
      }
    }
  }
}

TEST_CASE("hole metrics: a notch in any edge of the plate is not a hole", "[unit][analysis]") {
  // Reference: Hole (hole_metrics.hpp): a hole is an opening the plate closes around; an
  // opening that reaches the plate's outline is a notch. A 40 x 40 mm plate with a 10 mm
  // half-disc cut from the middle of each edge in turn, and from a corner.
  for (const Circle& c : std::vector<Circle>{{-20, 0, 5}, {20, 0, 5}, {0, -20, 5}, {0, 20, 5},
                                             {-20, -20, 5}}) {
    CAPTURE(c.x, c.y);
    const HolePlate p = holePlate(-20, -20, 40, 40, 2, {c});
    CHECK(findHoles(p.mesh.nodes, p.live).holes.empty());
  }
}

TEST_CASE("hole metrics: a piece hanging on by one node is the plate's", "[unit][analysis]") {
  // Reference: PlateHoles (hole_metrics.hpp): the plate proper is its largest connected
  // piece, elements joined through any shared node; loose pieces do not widen its extent.
  // A 40 x 40 mm plate and one tet that shares a single corner node with it, reaching 10 mm
  // past its edge: the extent grows by 10 mm along x. Cut loose, it does not.
  const HolePlate p = holePlate(-20, -20, 40, 40, 2, {});
  std::vector<Vec3> x = p.mesh.nodes;
  std::vector<std::array<int, 4>> tets = p.live;
  int corner = -1;  // the node at (20, 20, 0) mm
  for (std::size_t a = 0; a < x.size(); ++a)
    if ((x[a] - Vec3(20e-3, 20e-3, 0)).norm() < 1e-9) corner = static_cast<int>(a);
  REQUIRE(corner >= 0);
  const int n0 = static_cast<int>(x.size());
  x.push_back(Vec3(30e-3, 20e-3, 0));
  x.push_back(Vec3(25e-3, 25e-3, 0));
  x.push_back(Vec3(25e-3, 20e-3, -2e-3));
  tets.push_back({n0, n0 + 1, n0 + 2, corner});  // the shared node last
  HoleOptions o;
  o.normal = Vec3::UnitZ();  // the frame fixed, not taken from the nodes the tet adds
  const PlateHoles hanging = findHoles(x, tets, o);
  CHECK(hanging.u_max - hanging.u_min == Approx(50e-3).epsilon(1e-9));
  x.push_back(Vec3(20e-3, 20e-3, 0));  // the tet's own node where the corner is
  tets.back()[3] = n0 + 3;
  const PlateHoles loose = findHoles(x, tets, o);
  CHECK(loose.u_max - loose.u_min == Approx(40e-3).epsilon(1e-9));
}

TEST_CASE("hole metrics: a square hole's outline is the square, its corners cut by half a cell",
          "[unit][analysis]") {
  // Reference: Hole::outline (hole_metrics.hpp): it follows the raster cells with the
  // staircase corners cut. A 2 x 2 mm square hole (four cube columns) at 0.25 mm cells: its
  // sides are straight runs of cells, so the outline is the square with each corner cut by
  // half a cell: every point within half a cell of the square's sides, the area it encloses
  // that of the square less four corners of an eighth of a cell each (1e-9).
  const HolePlate p = holePlate(-20, -20, 40, 40, 2, {{0, 0, 1}});
  REQUIRE(p.true_area[0] == Approx(4e-6).epsilon(1e-12));
  const PlateHoles h = findHoles(p.mesh.nodes, p.live);
  REQUIRE(h.holes.size() == 1);
  const double cell = h.cell_size;
  REQUIRE(cell == Approx(0.25e-3).epsilon(1e-12));
  const std::vector<Vec3>& outline = h.holes[0].outline;
  CHECK(outline.size() == 8);
  for (const Vec3& a : outline) {
    const double off_side = std::min(std::abs(std::abs(a.x()) - 1e-3), std::abs(std::abs(a.y()) - 1e-3));
    CHECK(off_side <= 0.5 * cell + 1e-12);
  }
  CHECK(enclosedArea(outline) == Approx(4e-6 - 4 * 0.125 * cell * cell).epsilon(1e-9));
}

TEST_CASE("hole metrics: a hole round an island is outlined by its own edge, not the island's",
          "[unit][analysis]") {
  // Reference: Hole::outline (hole_metrics.hpp): the hole's outer edge, cell corners cut by
  // half a cell. An 8 x 8 mm square hole holding a comb-shaped island of 21 cube columns (its
  // edge, 44 mm, longer than the hole's 32 mm), joined to the plate by one sliver tet too thin
  // (0.02 mm) to cover any cell centre: one piece in 3D, an island on the raster. The hole is
  // the square less the island (43 mm^2, exact on cells aligned with the cubes); its outline
  // is the square with its four corners cut (64 mm^2 less four eighths of a cell, 1e-9). Up
  // to the thirty-fourth session the longest loop was taken, here the island's.
  const HolePlate p = holePlate(-20, -20, 40, 40, 2, {});
  const auto keep = [](double cx, double cy) {
    const bool in_hole = std::abs(cx) < 4 && std::abs(cy) < 4;
    const bool spine = cx == -2.5 && std::abs(cy) < 3;
    const bool tooth = cx > -2 && cx < 3 && (cy == -2.5 || cy == -0.5 || cy == 1.5);
    return !in_hole || spine || tooth;
  };
  std::vector<std::array<int, 4>> tets = columnsKept(p.mesh, keep);
  std::vector<Vec3> x = p.mesh.nodes;
  const auto node = [&](const Vec3& at) {
    for (std::size_t a = 0; a < x.size(); ++a)
      if ((x[a] - at).norm() < 1e-9) return static_cast<int>(a);
    FAIL("no node at " << at.transpose());
    return -1;
  };
  const int island = node(Vec3(-3e-3, 0, 0)), rim = node(Vec3(-4e-3, 0, 0));
  const int n0 = static_cast<int>(x.size());
  x.push_back(Vec3(-3.5e-3, 0.01e-3, -0.5e-3));
  x.push_back(Vec3(-3.5e-3, -0.01e-3, -1e-3));
  tets.push_back({island, rim, n0, n0 + 1});
  HoleOptions o;
  o.normal = Vec3::UnitZ();
  o.cell_size = 0.25e-3;
  const PlateHoles h = findHoles(x, tets, o);
  REQUIRE(h.holes.size() == 1);
  CHECK(h.holes[0].area == Approx(43e-6).epsilon(1e-12));
  const double cell = h.cell_size;
  CHECK(h.holes[0].outline.size() == 8);
  CHECK(enclosedArea(h.holes[0].outline) == Approx(64e-6 - 0.5 * cell * cell).epsilon(1e-9));
}

TEST_CASE("hole metrics: a hole wrapped round a piece held at its corners has one outline round "
          "it all",
          "[unit][analysis]") {
  // Reference: Hole::outline (hole_metrics.hpp); holes are 4-connected. An 8 x 8 mm square
  // hole round a 2 x 2 mm block held to the plate by a chain of two cube columns, each
  // meeting the next only at a cube edge: the hole (58 cube columns) runs round the block and
  // touches itself at those two corners. Its outline is one loop round the hole alone: on any
  // loop of cell edges without an island, each corner cut adds or takes an eighth of a cell
  // and the turns sum to four, so it encloses the hole's area less half a cell (1e-9). A
  // chain that crossed over at a corner where the hole touches itself would leave the block
  // in (64 mm^2) or its edge out.
  const HolePlate p = holePlate(-20, -20, 40, 40, 2, {});
  const auto keep = [](double cx, double cy) {
    const bool in_hole = std::abs(cx) < 4 && std::abs(cy) < 4;
    const bool block = cx > -2 && cx < 0 && cy > -2 && cy < 0;
    const bool chain = (cx == -2.5 && cy == -2.5) || (cx == -3.5 && cy == -3.5);
    return !in_hole || block || chain;
  };
  HoleOptions o;
  o.normal = Vec3::UnitZ();
  o.cell_size = 0.25e-3;
  const PlateHoles h = findHoles(p.mesh.nodes, columnsKept(p.mesh, keep), o);
  REQUIRE(h.holes.size() == 1);
  CHECK(h.holes[0].area == Approx(58e-6).epsilon(1e-12));
  const double cell = h.cell_size;
  CHECK(enclosedArea(h.holes[0].outline) == Approx(58e-6 - 0.5 * cell * cell).epsilon(1e-9));
}

TEST_CASE("hole metrics: a raster cell unrelated to the mesh stays within 2%", "[unit][analysis]") {
  const HolePlate p = holePlate(-30, -20, 60, 40, 3, {{-15, 0, 8}, {15, 5, 4}});
  HoleOptions o;
  o.cell_size = 0.23e-3;
  const PlateHoles h = findHoles(p.mesh.nodes, p.live, o);
  REQUIRE(h.holes.size() == 2);
  for (int k = 0; k < 2; ++k) CHECK(h.holes[k].area == Approx(p.true_area[k]).epsilon(0.02));
}

TEST_CASE("hole metrics: half model, hole on the symmetry edge", "[unit][analysis]") {
  // y in [0, 20] mm; a 12 mm hole centred on y = 0 is half a hole in the model.
  const HolePlate p = holePlate(-30, 0, 60, 20, 3, {{0, 0, 6}}, true);
  SECTION("without mirroring it is a notch in the edge, not a hole") {
    CHECK(findHoles(p.mesh.nodes, p.live).holes.empty());
  }
  SECTION("mirrored: the full-plate hole") {
    HoleOptions o;
    o.mirror = true;
    o.symmetry_axis = 1;
    o.symmetry_position = 0.0;
    const PlateHoles h = findHoles(p.mesh.nodes, p.live, o);
    REQUIRE(h.holes.size() == 1);
    CHECK(h.holes[0].area == Approx(p.true_area[0]).epsilon(0.02));
    CHECK(h.holes[0].on_symmetry);
    CHECK((h.holes[0].centroid - p.true_centroid[0]).norm() < 0.1e-3);
    // The extent is the full plate's: 60 mm along x, 2 x 20 mm across the plane.
    CHECK(std::abs(h.u.x()) == Approx(1.0));
    CHECK(h.u_max - h.u_min == Approx(60e-3).epsilon(1e-9));
    CHECK(h.v_max - h.v_min == Approx(40e-3).epsilon(1e-9));
  }
}

TEST_CASE("hole metrics: a half model mirrored on a plane off the origin", "[unit][analysis]") {
  // Reference: HoleOptions::symmetry_position: the image of a point is taken on that plane.
  // The half model of the test above moved to y in [5, 25] mm, its plane y = 5 mm: the same
  // full-plate hole (2 %), centred on the plane (0.1 mm), and the full plate's extent.
  const HolePlate p = holePlate(-30, 5, 60, 20, 3, {{0, 5, 6}}, true);
  HoleOptions o;
  o.mirror = true;
  o.symmetry_axis = 1;
  o.symmetry_position = 5e-3;
  const PlateHoles h = findHoles(p.mesh.nodes, p.live, o);
  REQUIRE(h.holes.size() == 1);
  CHECK(h.holes[0].area == Approx(p.true_area[0]).epsilon(0.02));
  CHECK(h.holes[0].on_symmetry);
  CHECK((h.holes[0].centroid - Vec3(0, 5e-3, -1.5e-3)).norm() < 0.1e-3);
  CHECK(h.v_max - h.v_min == Approx(40e-3).epsilon(1e-9));
}

TEST_CASE("hole metrics: a mirrored hole off the plane is not on the symmetry plane",
          "[unit][analysis]") {
  // Reference: HoleOptions / Hole (hole_metrics.hpp): on_symmetry marks a hole the symmetry
  // plane cuts, i.e. one with raster cells on both sides of it. The half model of the test
  // above with a second hole, 3 mm across y = 10 mm: mirrored, it and its image are two
  // holes on one side each.
  const HolePlate p = holePlate(-30, 0, 60, 20, 3, {{0, 0, 6}, {15, 10, 3}}, true);
  HoleOptions o;
  o.mirror = true;
  o.symmetry_axis = 1;
  const PlateHoles h = findHoles(p.mesh.nodes, p.live, o);
  REQUIRE(h.holes.size() == 3);
  for (const Hole& hole : h.holes) {
    INFO("hole at y = " << hole.centroid.y() * 1e3 << " mm");
    CHECK(hole.on_symmetry == (std::abs(hole.centroid.y()) < 1e-3));
  }
}

TEST_CASE("hole metrics: the raster never exceeds max_cells, and openings under four cells "
          "are left out", "[unit][analysis]") {
  // Reference: HoleOptions (hole_metrics.hpp). (1) A 40 x 40 mm plate of 1 mm cubes takes
  // a quarter-millimetre cell by default, 25,600 cells over its extent; with max_cells = 500
  // the cell grows by sqrt(25600 / 500) so that the extent holds 500 cells (1e-9). (2) One
  // removed 1 mm column (1 mm^2) with 1.1 mm cells is one cell, under four (4.84 mm^2): left
  // out by default, found with min_area = 0.5 mm^2.
  const HolePlate plate = holePlate(-20, -20, 40, 40, 2, {{0, 0, 7}});
  HoleOptions capped;
  capped.max_cells = 500;
  const PlateHoles h = findHoles(plate.mesh.nodes, plate.live, capped);
  CHECK(h.cell_size == Approx(0.25e-3 * std::sqrt(25600.0 / 500.0)).epsilon(1e-9));
  CHECK((h.u_max - h.u_min) * (h.v_max - h.v_min) / (h.cell_size * h.cell_size) ==
        Approx(500.0).epsilon(1e-9));
  REQUIRE(h.holes.size() == 1);  // the 14 mm hole, still found at 1.8 mm cells

  const HolePlate pin = holePlate(-20, -20, 40, 40, 2, {{0.5, 0.5, 0.4}});
  REQUIRE(pin.true_area[0] == Approx(1e-6).epsilon(1e-12));  // one column
  HoleOptions coarse;
  coarse.cell_size = 1.1e-3;
  CHECK(findHoles(pin.mesh.nodes, pin.live, coarse).holes.empty());
  coarse.min_area = 0.5e-6;
  const PlateHoles found = findHoles(pin.mesh.nodes, pin.live, coarse);
  REQUIRE(found.holes.size() == 1);
  CHECK(found.holes[0].area == Approx(1.21e-6).epsilon(1e-9));  // the one cell
}

TEST_CASE("hole metrics: no hole, and a loose plug does not close a hole", "[unit][analysis]") {
  SECTION("intact plate") {
    const HolePlate p = holePlate(-20, -20, 40, 40, 2, {});
    CHECK(findHoles(p.mesh.nodes, p.live).holes.empty());
  }
  SECTION("plug sheared off: only its ring of elements eroded, the plug pushed out") {
    // Erode the ring 5 mm < r < 7 mm; the plug inside is disconnected from the plate.
    HolePlate p = holePlate(-20, -20, 40, 40, 2, {{0, 0, 7}});
    const HolePlate full = p;
    std::vector<std::array<int, 4>> live;
    std::vector<Vec3> x = p.mesh.nodes;
    for (std::size_t e = 0; e < p.mesh.tets.size(); ++e) {
      const auto& t = p.mesh.tets[e];
      const auto [cx, cy] = columnCentre(x, t);
      if (!p.eroded[e] || std::hypot(cx, cy) < 5) live.push_back(t);
    }
    for (Vec3& q : x)
      if (std::hypot(q.x(), q.y()) < 4.9e-3) q.z() -= 4e-3;  // pushed behind the plate
    const PlateHoles h = findHoles(x, live);
    REQUIRE(h.holes.size() == 1);
    CHECK(h.holes[0].area == Approx(full.true_area[0]).epsilon(0.02));
    // The plate's extent is the plate proper's (40 x 40 mm): the plug, flung 100 mm to the
    // side, does not widen it.
    for (Vec3& q : x)
      if (std::hypot(q.x(), q.y()) < 4.9e-3) q.x() += 0.1;
    const PlateHoles far = findHoles(x, live);
    CHECK(far.u_max - far.u_min == Approx(40e-3).epsilon(1e-9));
    CHECK(far.v_max - far.v_min == Approx(40e-3).epsilon(1e-9));
  }
}

TEST_CASE("hole metrics: from a Model, and CSV/JSON output", "[unit][analysis]") {
  Model model = testing::boxModel(testing::elasticMaterial(), Vec3(40e-3, 30e-3, 2e-3), 40, 30, 2);
  const Circle hole{20, 15, 5};  // box model spans [0, 40] x [0, 30] mm
  double true_area = 0;
  for (int j = 0; j < 30; ++j)
    for (int i = 0; i < 40; ++i) true_area += hole.contains(i + 0.5, j + 0.5) ? 1e-6 : 0.0;
  for (std::size_t e = 0; e < model.elems.size(); ++e) {
    Vec3 c = Vec3::Zero();
    for (int n : model.elems.conn[e]) c += 0.25 * model.nodes.x[n];
    if (hole.contains(std::floor(c.x() * 1e3) + 0.5, std::floor(c.y() * 1e3) + 0.5))
      model.elems.status[e] = ElemStatus::Eroded;
  }
  const PlateHoles h = findHoles(model, 0);
  CHECK(h.plate == "box");
  REQUIRE(h.holes.size() == 1);
  CHECK(h.holes[0].area == Approx(true_area).epsilon(0.02));

  const auto dir = std::filesystem::temp_directory_path() /
                   ("fesph_holes_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  writeHolesCsv((dir / "holes.csv").string(), {h});
  writeHolesJson((dir / "holes.json").string(), {h}, "plastic_strain", 2.5e-5);
  std::ifstream csv(dir / "holes.csv");
  std::string header, row;
  std::getline(csv, header);
  std::getline(csv, row);
  CHECK(header.rfind("plate,hole,area_m2,diameter_m", 0) == 0);
  CHECK(row.rfind("box,1,", 0) == 0);
  std::stringstream json;
  json << std::ifstream(dir / "holes.json").rdbuf();
  CHECK(json.str().find("\"count\": 1") != std::string::npos);
  CHECK(json.str().find("\"outline_m\": [[") != std::string::npos);
  // what the images beside it show: the field and the output's time
  CHECK(json.str().find("\"field\": \"plastic_strain\", \"time_s\": 2.5e-05") !=
        std::string::npos);
  std::filesystem::remove_all(dir);
}

TEST_CASE("hole metrics: a plate made of particles, its holes and the plug it lost",
          "[unit][analysis]") {
  // Reference: findParticleHoles (hole_metrics.hpp). The plate of "two holes of known size"
  // (60 x 40 x 3 mm, a 16 mm and an 8 mm hole of whole 1 mm cube columns) as a body made of
  // particles, one per tet as fesph makes it. Particles resolve a hole's edge to about their
  // spacing s (twice the radius): each equivalent diameter within s of the true one, each
  // centroid within a tenth of s of the true one (the holes are symmetric about their
  // centres' lines, the particles not quite); the plate whole has no hole, and the plug of the
  // larger hole pushed out 6 mm behind the plate does not close it, nor failed particles in
  // place.
  const HolePlate p = holePlate(-30, -20, 60, 40, 3, {{-15, 0, 8}, {15, 5, 4}});
  const std::vector<DebrisParticle> particles = particlesOf(p);
  const double s = 2 * particles.front().radius;
  REQUIRE(s == Approx(2 * 0.5 * std::cbrt(1e-9 / 6)).epsilon(0.3));  // six tets a cube
  const Vec3 shift(0, 0, -6e-3);
  for (const bool plug : {false, true}) {
    CAPTURE(plug);
    const PlateHoles h = plug ? findParticleHoles(particlesOf(p, &shift)) : findParticleHoles(particles);
    REQUIRE(h.holes.size() == 2);
    CHECK(h.normal.z() == Approx(1.0).margin(1e-9));
    for (int k = 0; k < 2; ++k) {
      const double d = std::sqrt(4 * p.true_area[k] / M_PI);
      CAPTURE(k, h.holes[k].diameter, d, s);
      CHECK(std::abs(h.holes[k].diameter - d) <= s);
      CHECK((h.holes[k].centroid - p.true_centroid[k]).norm() <= 0.1 * s);
      CHECK_FALSE(h.holes[k].on_symmetry);
    }
    // the plate's faces (1.5 mm either side of its mid-plane): its extreme particle centres
    // and a radius beyond, within a tenth of a spacing
    CHECK(h.front == Approx(1.5e-3).margin(0.1 * s));
    CHECK(h.rear == Approx(-1.5e-3).margin(0.1 * s));
    CHECK(h.u_max - h.u_min == Approx(60e-3).margin(s));
    CHECK(h.v_max - h.v_min == Approx(40e-3).margin(s));
    // the default cell: a quarter of the spacing
    CHECK(h.cell_size <= 0.25 * s * 1.0001);
  }
  const HolePlate whole = holePlate(-30, -20, 60, 40, 3, {});
  CHECK(findParticleHoles(particlesOf(whole)).holes.empty());
  CHECK(findParticleHoles({}).holes.empty());

  // The holes' material still in place but failed (damage 1) is debris, as a failed element
  // is eroded: the holes stay, and the plate proper is the other particles. Damaged but not
  // failed, it is the plate's, and there is no hole.
  const Vec3 none = Vec3::Zero();
  std::vector<DebrisParticle> in_place = particlesOf(p, &none);
  std::vector<int> failed;
  for (std::size_t t = 0, i = 0; t < p.mesh.tets.size(); ++t, ++i)
    if (p.eroded[t]) in_place[i].damage = 1.0, failed.push_back(static_cast<int>(i));
  REQUIRE(failed.size() > 100);
  std::vector<int> proper;
  const PlateHoles h = findParticleHoles(in_place, {}, &proper);
  REQUIRE(h.holes.size() == 2);
  CHECK(std::abs(h.holes[0].diameter - std::sqrt(4 * p.true_area[0] / M_PI)) <= s);
  CHECK(proper.size() == in_place.size() - failed.size());
  CHECK(std::is_sorted(proper.begin(), proper.end()));
  for (int i : failed) CHECK_FALSE(std::binary_search(proper.begin(), proper.end(), i));
  for (int i : failed) in_place[static_cast<std::size_t>(i)].damage = 0.99;
  CHECK(findParticleHoles(in_place).holes.empty());
}

TEST_CASE("hole metrics: a half plate made of particles, hole on the symmetry edge",
          "[unit][analysis]") {
  // The half plate of "half model, hole on the symmetry edge" (y in [0, 20] mm, a 12 mm hole
  // centred on y = 0) made of particles: a notch unmirrored; mirrored, one full-plate hole on
  // the plane, its equivalent diameter within a spacing of the true one.
  const HolePlate p = holePlate(-30, 0, 60, 20, 3, {{0, 0, 6}}, true);
  const std::vector<DebrisParticle> particles = particlesOf(p);
  const double s = 2 * particles.front().radius;
  CHECK(findParticleHoles(particles).holes.empty());
  HoleOptions o;
  o.mirror = true;
  const PlateHoles h = findParticleHoles(particles, o);
  REQUIRE(h.holes.size() == 1);
  CHECK(h.holes[0].on_symmetry);
  CHECK(std::abs(h.holes[0].diameter - std::sqrt(4 * p.true_area[0] / M_PI)) <= s);
  CHECK(std::abs(h.holes[0].centroid.y()) <= 0.1 * s);
  CHECK(h.v_max - h.v_min == Approx(40e-3).margin(s));
}
