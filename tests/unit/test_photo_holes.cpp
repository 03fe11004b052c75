// SPDX-License-Identifier: MIT
// Photograph holes against a known hole map: a plate of 1 mm cubes with the cube columns inside
// two circles removed is the simulated plate; the synthetic photograph is drawn from the same
// removed columns (dark holes and background, a plate unevenly lit between 0.25 and 0.40,
// defocus blur, noise), so the true areas are the removed columns' areas.
#include "core/analysis/photo_holes.hpp"

#include "core/mesh/structured_box.hpp"

#include <catch2/catch.hpp>

#include <cmath>
#include <random>

using namespace fesph;

namespace {

constexpr double mm = 1e-3;

struct Circle {
  double x, y, r;  ///< mm, plate coordinates (centre of the plate at 0, 0)
};

/// 60 x 60 x 2 mm plate of 1 mm cubes centred on (0, 0), z in [-2, 0] mm, with the columns
/// whose centre lies in one of `holes` removed.
struct KnownPlate {
  std::vector<Vec3> x;
  std::vector<std::array<int, 4>> tets;
  std::vector<Circle> holes;
  /// Is the plate point (a, b) mm in a removed column?
  bool inHole(double a, double b) const {
    if (std::abs(a) >= 30 || std::abs(b) >= 30) return false;
    const double ca = std::floor(a) + 0.5, cb = std::floor(b) + 0.5;
    for (const Circle& c : holes)
      if (std::hypot(ca - c.x, cb - c.y) < c.r) return true;
    return false;
  }
  double trueArea(const Circle& c) const {  // m^2
    int n = 0;
    for (int j = -30; j < 30; ++j)
      for (int i = -30; i < 30; ++i) n += std::hypot(i + 0.5 - c.x, j + 0.5 - c.y) < c.r;
    return n * mm * mm;
  }
};

KnownPlate knownPlate(const std::vector<Circle>& holes) {
  KnownPlate p;
  p.holes = holes;
  const TetMesh mesh = structuredBox(Vec3(-30 * mm, -30 * mm, -2 * mm), Vec3(60 * mm, 60 * mm, 2 * mm), 60, 60, 2);
  p.x = mesh.nodes;
  for (const auto& t : mesh.tets) {
    const Vec3 c = 0.25 * (p.x[t[0]] + p.x[t[1]] + p.x[t[2]] + p.x[t[3]]);
    if (!p.inHole(c.x() / mm, c.y() / mm)) p.tets.push_back(t);
  }
  return p;
}

/// A photograph of the front face (right = +x, up = +y) at `mm_px` mm per pixel, the plate's
/// centre at pixel `centre`; rear = true mirrors it left-right (the rear face).
GrayImage photograph(const KnownPlate& plate, int w, int h, double mm_px, Eigen::Vector2d centre,
                     bool rear = false) {
  GrayImage ideal{w, h, std::vector<float>(static_cast<std::size_t>(w) * h)};
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const double a = (i + 0.5 - centre.x()) * mm_px * (rear ? -1 : 1);
      const double b = -(j + 0.5 - centre.y()) * mm_px;
      const bool material = std::abs(a) < 30 && std::abs(b) < 30 && !plate.inHole(a, b);
      // Light falls off from left to right and a little from top to bottom.
      const double lit = 0.40 - 0.12 * i / w - 0.03 * j / h;
      ideal.value[static_cast<std::size_t>(j) * w + i] = static_cast<float>(material ? lit : 0.04);
    }
  // Defocus: a 3 x 3 box blur; then noise of standard deviation 0.03 (Box-Muller on a fixed
  // seed, so the photograph is the same on every run).
  GrayImage photo = ideal;
  std::mt19937 rng(12345);
  const auto uniform = [&] { return (rng() + 0.5) / 4294967296.0; };
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      double s = 0;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di)
          s += ideal.at(std::clamp(i + di, 0, w - 1), std::clamp(j + dj, 0, h - 1));
      const double noise = 0.03 * std::sqrt(-2 * std::log(uniform())) * std::cos(2 * M_PI * uniform());
      photo.value[static_cast<std::size_t>(j) * w + i] = static_cast<float>(std::clamp(s / 9 + noise, 0.0, 1.0));
    }
  return photo;
}

const std::vector<Circle> kHoles = {{-10, -5, 8}, {12, 10, 5}};

/// An n x n square of black (0) pixels from column i0, row j0.
void darkSquare(GrayImage& img, int i0, int j0, int n) {
  for (int j = j0; j < j0 + n; ++j)
    for (int i = i0; i < i0 + n; ++i) img.value[static_cast<std::size_t>(j) * img.width + i] = 0.0f;
}

}  // namespace

TEST_CASE("Otsu's threshold splits a two-level histogram between its levels", "[unit][analysis]") {
  GrayImage img{100, 100, std::vector<float>(10000, 0.2f)};
  for (int k = 0; k < 3000; ++k) img.value[k] = 0.7f;
  const double t = otsuThreshold(img);
  CHECK(t > 0.2);
  CHECK(t <= 0.7);
}

TEST_CASE("photograph holes: count, areas and diameters of a known hole map", "[unit][analysis]") {
  const KnownPlate plate = knownPlate(kHoles);
  // 80 x 80 mm at 0.1 mm per pixel; the plate's centre off the image centre.
  const GrayImage photo = photograph(plate, 800, 800, 0.1, {413.0, 387.0});
  const PhotoSegmentation seg = segmentHoles(photo);
  CHECK(seg.automatic);
  // Otsu lands between the dark level (0.04) and the darkest plate (0.25).
  CHECK(seg.threshold > 0.06);
  CHECK(seg.threshold < 0.24);
  REQUIRE(seg.holes.size() == 2);
  CompareOptions o;
  o.m_per_px = 0.1 * mm;
  o.centre_px = Eigen::Vector2d(413.0, 387.0);
  const HoleComparison c = compareHoles(seg, simulatedPlate(plate.x, plate.tets), o);
  REQUIRE(c.photo.size() == 2);
  for (int k = 0; k < 2; ++k) {
    const double area = plate.trueArea(kHoles[k]);
    // Blur and noise move the thresholded edge by a fraction of a pixel (0.1 mm): within 4 %
    // on areas of 50 and 200 mm^2, 2 % on diameters, 0.1 mm on centroids.
    CHECK(c.photo[k].area == Approx(area).epsilon(0.04));
    CHECK(c.photo[k].diameter == Approx(std::sqrt(4 * area / M_PI)).epsilon(0.02));
    CHECK(std::abs(c.photo[k].centroid.x() - kHoles[k].x * mm) < 0.1 * mm);
    CHECK(std::abs(c.photo[k].centroid.y() - kHoles[k].y * mm) < 0.1 * mm);
  }
}

TEST_CASE("photograph holes: exact pixel counts of dark squares at a fixed threshold",
          "[unit][analysis]") {
  // Reference: the 3x3 binomial smoothing worked by hand. A 60 x 40 plate at 0.3 with dark
  // (0) squares: A 10 x 10 inside, B and C 10 x 10 on the top and bottom edges, D 4 x 4
  // inside. Smoothed, a pixel just inside a square's side keeps 4/16 of the plate's level
  // (0.075), one just outside it 12/16 (0.225), one diagonally outside a corner 15/16
  // (0.281), the plate away from the squares 16/16 (0.3). So at 0.15 a square is exactly its
  // pixels; at 0.27 it gains the row beside each side but not the corners (A: 100 + 40).
  // B and C touch the border: never holes. D (16 pixels) is under the default 25.
  GrayImage img{60, 40, std::vector<float>(60 * 40, 0.3f)};
  darkSquare(img, 10, 15, 10);  // A
  darkSquare(img, 30, 0, 10);   // B, on the top edge
  darkSquare(img, 45, 30, 10);  // C, on the bottom edge
  darkSquare(img, 30, 18, 4);   // D
  SegmentOptions o;
  o.threshold = 0.15;
  PhotoSegmentation seg = segmentHoles(img, o);
  REQUIRE(seg.holes.size() == 1);
  CHECK(seg.holes[0].area_px == 100);
  CHECK(seg.holes[0].centroid_px == Eigen::Vector2d(15.0, 20.0));  // pixel centres at i + 0.5
  std::size_t masked = 0;
  for (int l : seg.label) masked += l > 0;
  CHECK(masked == 100);
  o.min_area_px = 16;  // D is kept from 16 pixels on
  seg = segmentHoles(img, o);
  REQUIRE(seg.holes.size() == 2);
  CHECK(seg.holes[1].area_px == 16);
  CHECK(seg.holes[1].centroid_px == Eigen::Vector2d(32.0, 20.0));
  o.min_area_px = 17;
  CHECK(segmentHoles(img, o).holes.size() == 1);
  o.min_area_px = 0;
  o.threshold = 0.27;
  seg = segmentHoles(img, o);
  REQUIRE(seg.holes.size() == 2);
  CHECK(seg.holes[0].area_px == 140);
  CHECK(seg.holes[1].area_px == 32);  // 16 + 4 x 4: now over the default 25
  // Bright holes (a plate lit from behind): the negative image gives the same holes.
  for (float& v : img.value) v = 1.0f - v;
  o.dark_holes = false;
  o.threshold = 1 - 0.27;
  seg = segmentHoles(img, o);
  REQUIRE(seg.holes.size() == 2);
  CHECK(seg.holes[0].area_px == 140);
}

TEST_CASE("photograph holes: the threshold override is used", "[unit][analysis]") {
  const KnownPlate plate = knownPlate(kHoles);
  const GrayImage photo = photograph(plate, 800, 800, 0.1, {400.0, 400.0});
  SegmentOptions o;
  o.threshold = 0.5;  // above the whole (dark) plate: everything is "hole", one border piece
  const PhotoSegmentation seg = segmentHoles(photo, o);
  CHECK_FALSE(seg.automatic);
  CHECK(seg.threshold == 0.5);
  CHECK(seg.holes.empty());
  o.threshold = 1.5;
  CHECK_THROWS_AS(segmentHoles(photo, o), std::invalid_argument);
  for (const double t : {0.0, 1.0}) {  // (0, 1) is open: either end would make all one class
    o.threshold = t;
    CHECK_THROWS_AS(segmentHoles(photo, o), std::invalid_argument);
  }
}

TEST_CASE("simulated plate: a half plate mirrored off the origin spans the whole plate",
          "[unit][analysis]") {
  // Reference: the mirror image. A 40 x 30 mm half plate, y from 5 to 35 mm, mirrored on the
  // plane y = 5 mm is the 40 x 60 mm plate centred on (0, 5) mm; unmirrored it is its half.
  const TetMesh mesh = structuredBox(Vec3(-20 * mm, 5 * mm, -2 * mm), Vec3(40 * mm, 30 * mm, 2 * mm), 8, 6, 1);
  HoleOptions options;
  options.normal = Vec3::UnitZ();
  options.mirror = true;
  options.symmetry_axis = 1;
  options.symmetry_position = 5 * mm;
  for (const bool mirror : {true, false}) {
    options.mirror = mirror;
    INFO((mirror ? "mirrored" : "as meshed"));
    const SimulatedPlate plate = simulatedPlate(mesh.nodes, mesh.tets, options);
    const PlateHoles& h = plate.holes;
    // the extent along x and along y, whichever in-plane axis each is
    const Vec3 centre(0, mirror ? 5 * mm : 20 * mm, -1 * mm);
    const Eigen::Vector2d expected_centre((centre - h.origin).dot(h.u), (centre - h.origin).dot(h.v));
    CHECK((plate.centre - expected_centre).norm() < 1e-12);
    const double along_x = std::abs(h.u.x()) > 0.5 ? plate.half_size.x() : plate.half_size.y();
    const double along_y = std::abs(h.u.x()) > 0.5 ? plate.half_size.y() : plate.half_size.x();
    CHECK(along_x == Approx(20 * mm).epsilon(1e-12));
    CHECK(along_y == Approx(mirror ? 30 * mm : 15 * mm).epsilon(1e-12));
  }
}

TEST_CASE("photograph vs simulated hole map: IoU for the matching and a shifted map",
          "[unit][analysis]") {
  const KnownPlate plate = knownPlate(kHoles);
  const SimulatedPlate matching = simulatedPlate(plate.x, plate.tets);
  // The same holes 8 mm to the right on the plate.
  const KnownPlate moved = knownPlate({{-2, -5, 8}, {20, 10, 5}});
  const SimulatedPlate shifted = simulatedPlate(moved.x, moved.tets);
  const Eigen::Vector2d centre(413.0, 387.0);

  SECTION("front face, plate centre given") {
    const PhotoSegmentation seg = segmentHoles(photograph(plate, 800, 800, 0.1, centre));
    CompareOptions o;
    o.m_per_px = 0.1 * mm;
    o.centre_px = centre;
    const HoleComparison good = compareHoles(seg, matching, o);
    CHECK(good.iou >= 0.9);
    CHECK(good.simulated.size() == 2);
    CHECK(good.simulated_outside < 0.005);
    const HoleComparison bad = compareHoles(seg, shifted, o);
    CHECK(bad.iou < 0.5);
    // Discs 8 mm apart: lenses of 78.6 (r = 8 mm) and 8.2 mm^2 (r = 5 mm) over a union of
    // 472 mm^2, IoU 0.184.
    CHECK(bad.iou == Approx(0.184).margin(0.02));
  }
  SECTION("rear face: the photograph is mirrored") {
    const PhotoSegmentation seg = segmentHoles(photograph(plate, 800, 800, 0.1, centre, true));
    CompareOptions o;
    o.m_per_px = 0.1 * mm;
    o.centre_px = centre;
    o.rear = true;
    const HoleComparison rear = compareHoles(seg, matching, o);
    CHECK(rear.iou >= 0.9);
    // The photograph's holes in plate coordinates: mirrored back (0.1 mm, a pixel).
    REQUIRE(rear.photo.size() == 2);
    for (int k = 0; k < 2; ++k) {
      CHECK(std::abs(rear.photo[k].centroid.x() - kHoles[k].x * mm) < 0.1 * mm);
      CHECK(std::abs(rear.photo[k].centroid.y() - kHoles[k].y * mm) < 0.1 * mm);
    }
    o.rear = false;  // taken for the front face, the holes land mirrored
    CHECK(compareHoles(seg, matching, o).iou < 0.5);
  }
  SECTION("no centre given: the holes' centroids are aligned") {
    const PhotoSegmentation seg = segmentHoles(photograph(plate, 800, 800, 0.1, centre));
    CompareOptions o;
    o.m_per_px = 0.1 * mm;
    const HoleComparison c = compareHoles(seg, shifted, o);
    CHECK(c.iou >= 0.9);
    CHECK((c.frame.toPlate(centre) - Eigen::Vector2d(8 * mm, 0)).norm() < 0.1 * mm);
  }
  SECTION("a photograph of part of the plate: the simulated holes outside are not compared") {
    // 16 mm wide, its left edge 2 mm right of the plate's centre: the small hole (x 7..17 mm)
    // is inside, the big one (x -18..-2 mm) outside, the area share outside 200/280.
    const Eigen::Vector2d c(-20.0, 400.0);
    const PhotoSegmentation seg = segmentHoles(photograph(plate, 160, 800, 0.1, c));
    CompareOptions o;
    o.m_per_px = 0.1 * mm;
    o.centre_px = c;
    const HoleComparison part = compareHoles(seg, matching, o);
    CHECK(part.photo.size() == 1);
    CHECK(part.iou >= 0.9);
    CHECK(part.simulated_outside == Approx(plate.trueArea(kHoles[0]) /
                                           (plate.trueArea(kHoles[0]) + plate.trueArea(kHoles[1])))
                                        .margin(0.02));
  }
  SECTION("a wrong scale does not match") {
    const PhotoSegmentation seg = segmentHoles(photograph(plate, 800, 800, 0.1, centre));
    CompareOptions o;
    o.m_per_px = 0.13 * mm;
    o.centre_px = centre;
    CHECK(compareHoles(seg, matching, o).iou < 0.7);
    o.m_per_px = 0;
    CHECK_THROWS_AS(compareHoles(seg, matching, o), std::invalid_argument);
  }
}

TEST_CASE("polygon fill takes the pixels whose centre is inside", "[unit][analysis]") {
  // A 4 x 3 pixel rectangle from (1, 1) to (5, 4); a triangle's area within a pixel row.
  const auto mask = fillPolygons({{{1, 1}, {5, 1}, {5, 4}, {1, 4}}}, 8, 6);
  std::size_t n = 0;
  for (auto m : mask) n += m;
  CHECK(n == 12);
  CHECK(mask[1 * 8 + 1] == 1);
  CHECK(mask[0 * 8 + 1] == 0);
  CHECK(mask[1 * 8 + 5] == 0);
  // Edges off the pixel grid: y from 1.2 to 4.7 takes the rows whose centres 1.5 ... 4.5 it
  // spans (1 to 4), x from 0.4 to 3.4 the columns whose centres 0.5 ... 2.5 it spans (0 to 2).
  const auto off = fillPolygons({{{0.4, 1.2}, {3.4, 1.2}, {3.4, 4.7}, {0.4, 4.7}}}, 8, 6);
  for (int j = 0; j < 6; ++j)
    for (int i = 0; i < 8; ++i) {
      INFO("pixel " << i << ", " << j);
      CHECK(off[static_cast<std::size_t>(j) * 8 + i] == (j >= 1 && j <= 4 && i <= 2));
    }
  const auto tri = fillPolygons({{{0, 0}, {200, 0}, {0, 100}}}, 200, 100);
  n = 0;
  for (auto m : tri) n += m;
  CHECK(n == Approx(10000).epsilon(0.01));
}

TEST_CASE("polygon fill labels each pixel with its polygon, the later over the earlier",
          "[unit][analysis]") {
  // Rectangles x 0..4 and 2..6 on rows 0..2: columns 0-1 the first's, 2-5 the second's.
  const auto label = fillPolygons({{{0, 0}, {4, 0}, {4, 2}, {0, 2}}, {{2, 0}, {6, 0}, {6, 2}, {2, 2}}}, 8, 3);
  for (int i = 0; i < 8; ++i) {
    INFO("column " << i);
    CHECK(label[i] == (i < 2 ? 1 : i < 6 ? 2 : 0));
    CHECK(label[16 + i] == 0);  // row 2 lies below both
  }
}

TEST_CASE("photograph holes: each pixel is labelled with its hole, largest first",
          "[unit][analysis]") {
  // A 5 x 5 square found first (rows 4-8) and a 10 x 10 one below it (rows 20-29): sorted, the
  // larger is hole 1, and the labels follow the sorting, not the order of discovery.
  GrayImage img{40, 40, std::vector<float>(40 * 40, 0.3f)};
  darkSquare(img, 20, 4, 5);
  darkSquare(img, 5, 20, 10);
  SegmentOptions o;
  o.threshold = 0.15;  // each square exactly its pixels (see the test above)
  const PhotoSegmentation seg = segmentHoles(img, o);
  REQUIRE(seg.holes.size() == 2);
  CHECK(seg.holes[0].area_px == 100);
  CHECK(seg.holes[1].area_px == 25);
  std::size_t count[3] = {0, 0, 0};
  for (int l : seg.label) ++count[l];
  CHECK(count[1] == 100);
  CHECK(count[2] == 25);
  CHECK(seg.label[25 * 40 + 10] == 1);
  CHECK(seg.label[6 * 40 + 22] == 2);
}

TEST_CASE("photograph vs simulated holes, hole by hole: pairs, and holes on one side only",
          "[unit][analysis]") {
  // The photograph shows kHoles: 8 mm at (-10, -5) mm and 5 mm at (12, 10) mm. The simulated
  // plate has the large one and a 3 mm hole at (15, -15) mm of its own.
  const KnownPlate plate = knownPlate(kHoles);
  const Eigen::Vector2d centre(413.0, 387.0);
  const PhotoSegmentation seg = segmentHoles(photograph(plate, 800, 800, 0.1, centre));
  CompareOptions o;
  o.m_per_px = 0.1 * mm;
  o.centre_px = centre;

  SECTION("a pair and a hole on each side alone") {
    const KnownPlate other = knownPlate({{-10, -5, 8}, {15, -15, 3}});
    const HoleComparison c = compareHoles(seg, simulatedPlate(other.x, other.tets), o);
    REQUIRE(c.photo.size() == 2);
    REQUIRE(c.simulated.size() == 2);
    REQUIRE(c.pairs.size() == 1);
    CHECK(c.pairs[0].photo == 0);
    CHECK(c.pairs[0].simulated == 0);
    // The same removed columns: the overlap is the hole, to the photograph's edge pixels.
    CHECK(c.pairs[0].overlap == Approx(plate.trueArea(kHoles[0])).epsilon(0.04));
    CHECK(c.pairs[0].iou >= 0.9);
    CHECK(partnersOf(c, 0, true) == std::vector<std::size_t>{0});
    CHECK(partnersOf(c, 0, false) == std::vector<std::size_t>{0});
    CHECK(partnersOf(c, 1, true).empty());
    CHECK(partnersOf(c, 1, false).empty());
    // (12, 10) to (15, -15) mm: 25.18 mm, nearer than (-10, -5) mm at 26.63 mm; both holes'
    // centroids are those of their discs' removed columns (symmetric), to a pixel's tenth.
    CHECK(nearestOther(c, 1, true) == Approx(std::hypot(3.0, 25.0) * mm).margin(0.1 * mm));
    CHECK(nearestOther(c, 1, false) == Approx(std::hypot(3.0, 25.0) * mm).margin(0.1 * mm));
    CHECK(nearestOther(c, 0, true) < 0.1 * mm);
  }
  SECTION("the same map 8 mm off: each hole pairs with its own image, by its own lens") {
    // Discs r 8 mm 8 mm apart: lens 78.6 mm^2, union 323.5, IoU 0.243; r 5 mm: lens 8.2 mm^2,
    // union 148.9, IoU 0.055 (the removed columns approximate the discs to ~1 mm^2).
    const KnownPlate moved = knownPlate({{-2, -5, 8}, {20, 10, 5}});
    const HoleComparison c = compareHoles(seg, simulatedPlate(moved.x, moved.tets), o);
    REQUIRE(c.pairs.size() == 2);
    CHECK(c.pairs[0].photo == 0);
    CHECK(c.pairs[0].simulated == 0);
    CHECK(c.pairs[0].iou == Approx(0.243).margin(0.02));
    CHECK(c.pairs[1].photo == 1);
    CHECK(c.pairs[1].simulated == 1);
    CHECK(c.pairs[1].iou == Approx(0.055).margin(0.02));
  }
  SECTION("one simulated hole over two photographed holes: both pairs") {
    const KnownPlate merged = knownPlate({{1, 2.5, 18}});
    const HoleComparison c = compareHoles(seg, simulatedPlate(merged.x, merged.tets), o);
    REQUIRE(c.simulated.size() == 1);
    REQUIRE(c.pairs.size() == 2);
    CHECK(partnersOf(c, 0, false) == std::vector<std::size_t>{0, 1});
  }
  SECTION("without a centre the largest holes are aligned: a fragment hole does not pull") {
    // The simulated plate: the large hole alone, 8 mm to the right. Aligning all holes'
    // area-weighted centroids would put the photograph's 5 mm hole into the balance and shift
    // the plate by 78.5/(201 + 78.5) of (22, 15) mm.
    const KnownPlate moved = knownPlate({{-2, -5, 8}});
    o.centre_px.reset();
    const HoleComparison c = compareHoles(seg, simulatedPlate(moved.x, moved.tets), o);
    CHECK((c.frame.toPlate(centre) - Eigen::Vector2d(8 * mm, 0)).norm() < 0.1 * mm);
    REQUIRE(c.pairs.size() == 1);
    CHECK(c.pairs[0].iou >= 0.9);
    CHECK(partnersOf(c, 1, true).empty());  // the 5 mm hole: photographed only
  }
}
