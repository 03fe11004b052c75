// SPDX-License-Identifier: MIT
// What the plate images promise beyond a hole drawn at the right scale (test_images.cpp), each
// on a synthetic run written with SeriesWriter and read back from its PNGs:
// - a half model is drawn whole: the mirrored plate, the whole hole, the mirrored particles;
// - a colour means the same value in every image: damage on [0, 1], plastic strain from 0,
//   stresses in MPa, one colour range for all plates;
// - all plates at one scale, the widest whole in the frame, a scale bar of a round length;
// - only particles near a plate drawn with it, and hidden behind it in the rear view;
// - the output step nearest the time asked for;
// - the section view: plastic strain on a half model's symmetry plane, every plate framed.
#include "render/photo_compare.hpp"
#include "render/plate_images.hpp"
#include "render/section_view.hpp"
#include "render/series_writer.hpp"

#include "core/mesh/structured_box.hpp"
#include "core/sph/particle_body.hpp"
#include "tests/render/png_image.hpp"
#include "tests/support/models.hpp"
#include "tests/support/temp_folder.hpp"

#include <catch2/catch.hpp>

#include <vtkActor.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkGlyph3DMapper.h>
#include <vtkLookupTable.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <tuple>

using namespace fesph;
using namespace fesph::testing;
namespace fs = std::filesystem;

namespace {

constexpr double mm = 1e-3;

/// One plate: a box of 1 mm cubes from `lo` (whole mm) of `size`; the cube columns whose
/// centre lies within hole_radius of the z axis are eroded, every other element's state is
/// set by fill(centre of its cube column, state).
struct PlateSpec {
  std::string name;
  Vec3 lo, size;
  double hole_radius = 0;
  std::function<void(const Vec3&, PointState&)> fill = [](const Vec3&, PointState&) {};
  /// Made of particles: one of 1 mm^3 at each cube's centre, those of the hole's columns left
  /// out (the hole is then in the model from the start).
  bool particles = false;
};

/// The centre of the 1 mm cube column (whole mm in x and y) that holds x.
Vec3 columnOf(const Vec3& x) {
  return Vec3((std::floor(x.x() / mm) + 0.5) * mm, (std::floor(x.y() / mm) + 0.5) * mm, 0.0);
}

struct RunSpec {
  std::vector<PlateSpec> plates;
  bool half = false;            ///< scene.toml: symmetry = "half" (the plane y = 0)
  std::vector<Vec3> particles;  ///< a particle body "debris" after the plates, 1 mm^3 each
  std::function<void(PointState&)> debris_fill = [](PointState&) {};  ///< their state
};

/// The model of a run: the plates (bodies 0, 1, ...) and then the debris particles.
Model buildRun(const RunSpec& spec) {
  Model model;
  model.materials.push_back(elasticMaterial());
  for (const PlateSpec& p : spec.plates) {
    const auto cells = [](double length) { return static_cast<int>(std::lround(length / mm)); };
    if (!p.particles) {
      addBody(model, p.name,
              structuredBox(p.lo, p.size, cells(p.size.x()), cells(p.size.y()), cells(p.size.z())),
              0, Placement{}, Vec3::Zero(), false);
      continue;
    }
    std::vector<Vec3> centres;
    for (int k = 0; k < cells(p.size.z()); ++k)
      for (int j = 0; j < cells(p.size.y()); ++j)
        for (int i = 0; i < cells(p.size.x()); ++i) {
          const Vec3 c = p.lo + Vec3(i + 0.5, j + 0.5, k + 0.5) * mm;
          if (columnOf(c).norm() >= p.hole_radius) centres.push_back(c);
        }
    addParticleBody(model, p.name, centres, std::vector<double>(centres.size(), mm * mm * mm), 0,
                    Vec3::Zero(), false);
  }
  if (!spec.particles.empty())
    addParticleBody(model, "debris", spec.particles,
                    std::vector<double>(spec.particles.size(), mm * mm * mm), 0, Vec3::Zero(),
                    false);
  finaliseModel(model);
  return model;
}

/// Erosion and states of the plates as their specs say.
void shapePlates(Model& model, const RunSpec& spec) {
  for (std::size_t b = 0; b < spec.plates.size(); ++b) {
    const Body& body = model.bodies[b];
    for (std::size_t i = 0; i < model.particles.size(); ++i)
      if (model.particles.body[i] == static_cast<int>(b))
        spec.plates[b].fill(columnOf(model.particles.x[i]), model.particles.state[i]);
    for (std::size_t e = body.elem_begin; e < body.elem_end; ++e) {
      Vec3 c = Vec3::Zero();
      for (int n : model.elems.conn[e]) c += 0.25 * model.nodes.x0[n];
      const Vec3 column = columnOf(c);
      model.elems.status[e] = column.norm() < spec.plates[b].hole_radius ? ElemStatus::Eroded
                                                                         : ElemStatus::Live;
      spec.plates[b].fill(column, model.elems.state[e]);
    }
  }
}

void writeScene(const fs::path& dir, const RunSpec& spec) {
  std::ofstream scene(dir / "scene.toml");
  if (spec.half) scene << "[simulation]\nsymmetry = \"half\"\n";
  for (const PlateSpec& p : spec.plates) scene << "[[bodies]]\nname = \"" << p.name << "\"\n";
  // the debris particles a projectile's (a body of particles that is none is a plate, drawn)
  if (!spec.particles.empty()) scene << "[[bodies]]\nname = \"debris\"\nprojectile = true\n";
}

/// A run of one output step at 10 us.
void writePlateRun(const fs::path& dir, const RunSpec& spec) {
  Model model = buildRun(spec);
  shapePlates(model, spec);
  for (std::size_t i = 0; i < model.particles.size(); ++i)
    if (model.particles.body[i] == static_cast<int>(spec.plates.size()))
      spec.debris_fill(model.particles.state[i]);
  SeriesWriter(dir).write(model, 10e-6);
  writeScene(dir, spec);
}

/// Area of the 1 mm cube columns within `radius` of the axis over the full plane (m^2).
double columnArea(double radius) {
  double area = 0;
  for (int j = -40; j < 40; ++j)
    for (int i = -40; i < 40; ++i)
      if (std::hypot(i + 0.5, j + 0.5) * mm < radius) area += mm * mm;
  return area;
}

ImageOptions options800x600(const std::string& field = "damage") {
  ImageOptions options;
  options.width = 800;
  options.height = 600;
  options.field = field;
  return options;
}

/// Pixel coordinates of the centre of the scene viewport, where the plates' extent centre is.
struct Centre {
  int x, y;
};
Centre sceneCentre(const Image& img) {
  using render_detail::kSceneViewport;
  return {static_cast<int>(0.5 * (kSceneViewport[0] + kSceneViewport[2]) * img.width),
          static_cast<int>(0.5 * (kSceneViewport[1] + kSceneViewport[3]) * img.height)};
}

/// Brightness of a pixel: viridis grows brighter from its bottom (purple) to its top (yellow).
int brightness(const unsigned char* p) { return p[0] + p[1] + p[2]; }

/// Largest difference of one channel between two pixels.
int colourDistance(const unsigned char* p, const unsigned char* q) {
  return std::max({std::abs(p[0] - q[0]), std::abs(p[1] - q[1]), std::abs(p[2] - q[2])});
}

std::array<unsigned char, 3> debrisColour(int body) {
  double c[3];
  render_detail::bodyColour(body, c);
  return {static_cast<unsigned char>(255 * c[0]), static_cast<unsigned char>(255 * c[1]),
          static_cast<unsigned char>(255 * c[2])};
}

/// A 40 x 40 x 2 mm plate, front face z = 0, with a hole of `radius` and a uniform state.
PlateSpec squarePlate(const std::string& name, double radius,
                      std::function<void(const Vec3&, PointState&)> fill) {
  return {name, Vec3(-20 * mm, -20 * mm, -2 * mm), Vec3(40 * mm, 40 * mm, 2 * mm), radius,
          std::move(fill)};
}

}  // namespace

TEST_CASE("a half model's plate images show the whole plate, its whole hole and the mirrored particles",
          "[unit][render]") {
  unsetenv("DISPLAY");
  TempFolder dir("plate_half");
  RunSpec spec;
  spec.half = true;  // the plate's half y > 0, the hole's half, particles at y = 15 mm
  spec.plates.push_back(
      {"plate", Vec3(-20 * mm, 0, -2 * mm), Vec3(40 * mm, 20 * mm, 2 * mm), 6 * mm});
  for (int k = 0; k < 5; ++k) spec.particles.push_back(Vec3((14 + k) * mm, 15 * mm, 0.7 * mm));
  writePlateRun(dir.path, spec);
  const std::vector<PlateImages> images =
      renderPlateImages(dir.path.string(), -1, options800x600(), (dir.path / "images").string());
  REQUIRE(images.size() == 1);
  const PlateImages& plate = images[0];
  const double full_area = columnArea(6 * mm);
  REQUIRE(plate.holes.holes.size() == 1);
  CHECK(plate.holes.holes[0].area == Approx(full_area).epsilon(0.02));

  // The whole hole is white in the front view, and nothing else of the plate is: the white
  // pixels within 17 mm of the centre cover the full hole, not the half hole and the missing
  // half plate.
  const Image front = readPng(plate.front_png);
  const Centre c = sceneCentre(front);
  const int half = static_cast<int>(17 * mm / plate.pixel_size);
  const std::size_t hole_px = front.count(white, c.x - half, c.y - half, c.x + half, c.y + half);
  CHECK(hole_px * plate.pixel_size * plate.pixel_size == Approx(full_area).epsilon(0.05));

  // The particles and their mirror images: on both sides of the symmetry plane's image.
  const std::array<unsigned char, 3> orange = debrisColour(1);
  const auto isDebris = [&](const unsigned char* p) { return near(p, orange.data(), 60); };
  const int w = front.width;
  CHECK(front.count(isDebris, 0, c.y + 2, w - 1, front.height - 1) > 50);
  CHECK(front.count(isDebris, 0, 0, w - 1, c.y - 2) > 50);
}

TEST_CASE("plate image colours mean the same value in every image", "[unit][render]") {
  unsetenv("DISPLAY");
  // The colour at the centre of a plate of uniform `value` of `field`, hole-free.
  const auto centreColour = [](const std::string& field, double value) {
    TempFolder dir("plate_colour");
    RunSpec spec;
    spec.plates.push_back(squarePlate("plate", 0, [&](const Vec3&, PointState& st) {
      if (field == "damage") st.damage = value;
      if (field == "plastic_strain") st.eps_p = value;
    }));
    writePlateRun(dir.path, spec);
    const Image front = readPng(renderPlateImages(dir.path.string(), -1, options800x600(field),
                                                  (dir.path / "images").string())[0]
                                    .front_png);
    const Centre c = sceneCentre(front);
    const unsigned char* p = front.at(c.x, c.y);
    return std::array<unsigned char, 3>{p[0], p[1], p[2]};
  };
  SECTION("damage on [0, 1] whatever the plate's own range") {
    // A plate damaged 0.3 throughout and one damaged 0.7: a range from their own values
    // would draw both in the colour map's bottom colour.
    const auto low = centreColour("damage", 0.3), high = centreColour("damage", 0.7);
    CHECK(brightness(high.data()) > brightness(low.data()) + 60);
  }
  SECTION("plastic strain from 0") {
    const auto none = centreColour("plastic_strain", 0.0);
    const auto some = centreColour("plastic_strain", 0.4);  // the top of a range [0, 0.4]
    CHECK(brightness(some.data()) > brightness(none.data()) + 200);
  }
}

TEST_CASE("plate images draw stresses in MPa on a range in MPa", "[unit][render]") {
  unsetenv("DISPLAY");
  TempFolder dir("plate_pressure");
  RunSpec spec;  // 100 MPa for x < 0, 300 MPa for x > 0: the range's two ends
  spec.plates.push_back(squarePlate("plate", 0, [](const Vec3& column, PointState& st) {
    st.p = column.x() < 0 ? 100e6 : 300e6;
  }));
  writePlateRun(dir.path, spec);
  const PlateImages plate = renderPlateImages(dir.path.string(), -1, options800x600("pressure"),
                                              (dir.path / "images").string())[0];
  const Image front = readPng(plate.front_png);
  const Centre c = sceneCentre(front);
  // 10 mm either side of the centre along each image axis; the halves lie along one of them.
  const int d = static_cast<int>(10 * mm / plate.pixel_size);
  const int across_x = colourDistance(front.at(c.x - d, c.y), front.at(c.x + d, c.y));
  const int across_y = colourDistance(front.at(c.x, c.y - d), front.at(c.x, c.y + d));
  CHECK(std::max(across_x, across_y) > 100);
}

TEST_CASE("plate images share one scale and one colour range", "[unit][render]") {
  unsetenv("DISPLAY");
  TempFolder dir("plate_two");
  RunSpec spec;  // a 40 mm plate strained 0.8 and, 30 mm behind it, a 20 mm one strained 0.2
  spec.plates.push_back(squarePlate("first", 0, [](const Vec3&, PointState& st) { st.eps_p = 0.8; }));
  spec.plates.push_back({"second", Vec3(-10 * mm, -10 * mm, -32 * mm), Vec3(20 * mm, 20 * mm, 2 * mm), 0,
                         [](const Vec3&, PointState& st) { st.eps_p = 0.2; }});
  writePlateRun(dir.path, spec);
  const std::vector<PlateImages> images = renderPlateImages(
      dir.path.string(), -1, options800x600("plastic_strain"), (dir.path / "images").string());
  REQUIRE(images.size() == 2);
  CHECK(images[1].pixel_size == images[0].pixel_size);
  const Image first = readPng(images[0].front_png), second = readPng(images[1].front_png);
  // The second plate at the first one's scale: a quarter of its area, not zoomed to fill.
  const std::size_t second_px = second.count([](const unsigned char* p) { return !white(p); },
                                             0, static_cast<int>(0.08 * 600), 800 * 84 / 100,
                                             static_cast<int>(0.9 * 600));
  const double px2 = images[0].pixel_size * images[0].pixel_size;
  CHECK(second_px * px2 == Approx(20 * mm * 20 * mm).epsilon(0.05));
  // 0.8 at the range's top, 0.2 at a quarter of it: a range from the second plate's own
  // values would draw both at the top.
  const Centre c = sceneCentre(first);
  CHECK(brightness(first.at(c.x, c.y)) > brightness(second.at(c.x, c.y)) + 100);
}

TEST_CASE("plate images frame the plate whole, with a scale bar of a round length",
          "[unit][render]") {
  unsetenv("DISPLAY");
  TempFolder dir("plate_wide");
  RunSpec spec;  // 80 x 20 mm: its width, not its height, sets the frame
  spec.plates.push_back({"plate", Vec3(-40 * mm, -10 * mm, -2 * mm), Vec3(80 * mm, 20 * mm, 2 * mm)});
  writePlateRun(dir.path, spec);
  const PlateImages plate =
      renderPlateImages(dir.path.string(), -1, options800x600(), (dir.path / "images").string())[0];
  const Image front = readPng(plate.front_png);
  const Centre c = sceneCentre(front);
  using render_detail::kSceneViewport;
  const int left = static_cast<int>(kSceneViewport[0] * 800) + 1;
  const int right = static_cast<int>(kSceneViewport[2] * 800) - 1;
  // Along the middle row: the plate's full width in pixels, with white margins on both sides.
  const auto plateRow = [&](const Image& img) {
    return img.count([](const unsigned char* p) { return !white(p); }, left, c.y, right, c.y);
  };
  CHECK(plateRow(front) * plate.pixel_size == Approx(80 * mm).margin(3 * plate.pixel_size));
  CHECK(white(front.at(left, c.y)));
  CHECK(white(front.at(right, c.y)));

  // The scale bar: a dark line at 3.5 % of the height from 4 % of the width, 1, 2 or 5 times
  // a power of ten long, the longest such length within a fifth of the scene's width.
  // The line is two pixels wide: the longest dark run of the rows about its height.
  int run = 0;
  for (int y = static_cast<int>(0.035 * 600) - 1; y <= static_cast<int>(0.035 * 600) + 1; ++y) {
    const auto dark = [&](int x) { return brightness(front.at(x, y)) < 3 * 128; };
    int x = static_cast<int>(0.04 * 800) - 3;
    while (x < 800 && !dark(x)) ++x;
    const int start = x;
    while (x < 800 && dark(x)) ++x;
    run = std::max(run, x - start);
  }
  // From tick centre to tick centre: the run less one line width (2 pixels at this height).
  const double bar = (run - 2) * plate.pixel_size;
  const double scene_width = (right - left) * plate.pixel_size;
  const double decade = std::pow(10.0, std::floor(std::log10(bar)));
  const double mantissa = bar / decade;
  const double round_length =
      (mantissa < 1.5 ? 1.0 : mantissa < 3.5 ? 2.0 : mantissa < 7.5 ? 5.0 : 10.0) * decade;
  CHECK(bar == Approx(round_length).margin(1.5 * plate.pixel_size));
  CHECK(round_length <= 0.2 * scene_width);
  CHECK(round_length > 0.2 * scene_width / 2.5);  // the next round length would not fit
}

TEST_CASE("plate images draw the particles near the plate only, hidden from the rear",
          "[unit][render]") {
  unsetenv("DISPLAY");
  TempFolder dir("plate_particles");
  RunSpec spec;
  spec.plates.push_back(squarePlate("plate", 0, [](const Vec3&, PointState&) {}));
  // Three on the front face near (12, 12) mm, three 30 mm in front of it near (-12, -12) mm.
  for (int k = 0; k < 3; ++k) spec.particles.push_back(Vec3((11 + k) * mm, 12 * mm, 0.7 * mm));
  for (int k = 0; k < 3; ++k) spec.particles.push_back(Vec3(-(11 + k) * mm, -12 * mm, 30 * mm));
  writePlateRun(dir.path, spec);
  const PlateImages plate =
      renderPlateImages(dir.path.string(), -1, options800x600(), (dir.path / "images").string())[0];
  const std::array<unsigned char, 3> orange = debrisColour(1);
  const auto isDebris = [&](const unsigned char* p) { return near(p, orange.data(), 60); };
  const Image front = readPng(plate.front_png);
  const Centre c = sceneCentre(front);
  // The near particles in one quadrant, the far ones (which would lie in the opposite one)
  // left out: they are 30 mm in front of a 2 mm plate.
  // Quadrants about the centre, each followed by the one diagonally opposite.
  const std::size_t q[4] = {front.count(isDebris, c.x, c.y, 799, 599),
                            front.count(isDebris, 0, c.y, c.x - 1, 599),
                            front.count(isDebris, 0, 0, c.x - 1, c.y - 1),
                            front.count(isDebris, c.x, 0, 799, c.y - 1)};
  const int near_quadrant = static_cast<int>(std::max_element(q, q + 4) - q);
  CHECK(q[near_quadrant] > 50);
  CHECK(q[(near_quadrant + 2) % 4] == 0);
  // From the rear the plate hides the particles on its front face.
  CHECK(readPng(plate.rear_png).count(isDebris) == 0);
}

TEST_CASE("plate images show the output step nearest the time asked for", "[unit][render]") {
  unsetenv("DISPLAY");
  TempFolder dir("plate_steps");
  RunSpec spec;  // a 4 mm hole at 10 us, grown to 6 mm at 20 us
  spec.plates.push_back(squarePlate("plate", 4 * mm, [](const Vec3&, PointState&) {}));
  Model model = buildRun(spec);
  shapePlates(model, spec);
  SeriesWriter series(dir.path);
  series.write(model, 10e-6);
  spec.plates[0].hole_radius = 6 * mm;
  shapePlates(model, spec);
  series.write(model, 20e-6);
  writeScene(dir.path, spec);

  const auto imagesAt = [&](double time) {
    return renderPlateImages(dir.path.string(), time, options800x600(),
                             (dir.path / "images").string())[0];
  };
  for (const auto& [asked, shown, radius] : {std::tuple{12e-6, 10e-6, 4 * mm},
                                             std::tuple{16e-6, 20e-6, 6 * mm},
                                             std::tuple{-1.0, 20e-6, 6 * mm}}) {
    CAPTURE(asked);
    const PlateImages plate = imagesAt(asked);
    CHECK(plate.time == Approx(shown));
    REQUIRE(plate.holes.holes.size() == 1);
    CHECK(plate.holes.holes[0].area == Approx(columnArea(radius)).epsilon(0.02));
  }
}

TEST_CASE("colour bar ranges are round and hold the values", "[unit][render]") {
  struct Case {
    double lo, hi, nice_lo, nice_hi;
    int labels;
  };
  // (hi - lo) / 5 rounded up to 1, 2, 2.5 or 5 times a power of ten; the ends onto its
  // multiples, outwards.
  for (const Case& k : {Case{0, 1.2, 0, 1.25, 6}, Case{0.3, 1.2, 0.2, 1.2, 6},
                        Case{-3, 7, -4, 8, 7}, Case{0, 0.4, 0, 0.4, 5},
                        Case{310, 1840, 0, 2000, 5}}) {
    double lo = k.lo, hi = k.hi;
    const int labels = render_detail::niceRange(lo, hi);
    CAPTURE(k.lo, k.hi);
    CHECK(lo == Approx(k.nice_lo).margin(1e-12));
    CHECK(hi == Approx(k.nice_hi).margin(1e-12));
    CHECK(labels == k.labels);
  }
  double scale = 0;
  CHECK(render_detail::fieldTitle("pressure", &scale) == "Pressure (MPa)");
  CHECK(scale == 1e-6);
  CHECK(render_detail::fieldTitle("von_mises", &scale) == "von Mises stress (MPa)");
  CHECK(scale == 1e-6);
  CHECK(render_detail::fieldTitle("damage", &scale) == "Damage");
  CHECK(scale == 1.0);
}

TEST_CASE("the section view shows plastic strain from 0 on a half model's symmetry plane",
          "[unit][render]") {
  unsetenv("DISPLAY");
  TempFolder dir("section_half");
  RunSpec spec;  // half a 40 mm plate (y > 0), strained 0.4 throughout, undamaged
  spec.half = true;
  spec.plates.push_back({"plate", Vec3(-20 * mm, 0, -2 * mm), Vec3(40 * mm, 20 * mm, 2 * mm), 0,
                         [](const Vec3&, PointState& st) { st.eps_p = 0.4; }});
  // On the plane in front of the plate at x = 5 mm, off it at x = -5 mm, and one a metre off.
  spec.particles = {Vec3(5 * mm, 0, 1 * mm), Vec3(-5 * mm, 15 * mm, 1 * mm), Vec3(1.0, 0, 0)};
  writePlateRun(dir.path, spec);
  // The plate images' default field, damage: the section shows plastic strain instead.
  const Image img = readPng(renderSectionView(dir.path.string(), -1, options800x600(),
                                              (dir.path / "section.png").string()));
  const Centre c = sceneCentre(img);
  // x is up: the cut plate is a vertical bar 40 mm high filling the frame's height, in the
  // colour of the top of a range from 0 to 0.4 (yellow), not of its bottom (purple).
  const int vp_h = static_cast<int>(0.82 * 600);
  const std::size_t column = img.count([](const unsigned char* p) { return !white(p); }, c.x,
                                       0, c.x, 599);
  CHECK(column > static_cast<std::size_t>(0.9 * vp_h));
  CHECK(brightness(img.at(c.x, c.y)) > 450);
  // The particle on the plane is drawn (above the centre), the one 15 mm off it is not.
  // (Particles take the field's colours here: unstrained, the map's bottom.)
  const auto notPlate = [&](const unsigned char* p) {
    return !white(p) && colourDistance(p, img.at(c.x, c.y)) > 60;
  };
  CHECK(img.count(notPlate, 0, c.y + 10, 672, 540) > 20);
  CHECK(img.count(notPlate, 0, 48, 672, c.y - 10) == 0);
}

TEST_CASE("the section view's colours hold the particles' values", "[unit][render]") {
  // The plate of "the section view shows plastic strain from 0" (strained 0.4) with particles
  // on the plane in front of it strained 0.8: the colours span [0, 0.8], the plate in the
  // middle of the map (teal), not at its top (yellow) with the particles beyond it.
  unsetenv("DISPLAY");
  TempFolder dir("section_particles");
  RunSpec spec;
  spec.half = true;
  spec.plates.push_back({"plate", Vec3(-20 * mm, 0, -2 * mm), Vec3(40 * mm, 20 * mm, 2 * mm), 0,
                         [](const Vec3&, PointState& st) { st.eps_p = 0.4; }});
  spec.particles = {Vec3(5 * mm, 0, 1 * mm), Vec3(6 * mm, 0, 1 * mm)};
  spec.debris_fill = [](PointState& st) { st.eps_p = 0.8; };
  writePlateRun(dir.path, spec);
  const Image img = readPng(renderSectionView(dir.path.string(), -1, options800x600(),
                                              (dir.path / "section.png").string()));
  const Centre c = sceneCentre(img);
  // the cut plate is the vertical bar through the frame's middle row, left of the particles
  int x = 17;
  while (x < c.x && white(img.at(x, c.y))) ++x;
  REQUIRE(x < c.x);
  CHECK(brightness(img.at(x + 2, c.y)) < 400);
  CHECK(brightness(img.at(x + 2, c.y)) > 200);
}

TEST_CASE("the section view frames every plate along the flight", "[unit][render]") {
  unsetenv("DISPLAY");
  TempFolder dir("section_two");
  RunSpec spec;  // two 20 mm plates 60 mm apart: the flight direction (z) sets the frame
  spec.plates.push_back({"front", Vec3(-10 * mm, -10 * mm, -2 * mm), Vec3(20 * mm, 20 * mm, 2 * mm)});
  spec.plates.push_back({"back", Vec3(-10 * mm, -10 * mm, -62 * mm), Vec3(20 * mm, 20 * mm, 2 * mm)});
  writePlateRun(dir.path, spec);
  const Image img = readPng(renderSectionView(dir.path.string(), -1, options800x600(),
                                              (dir.path / "section.png").string()));
  const Centre c = sceneCentre(img);
  const auto solid = [](const unsigned char* p) { return !white(p); };
  // -z to the right: the front plate in the left half of the frame, the back one in the right.
  const std::size_t left = img.count(solid, 17, 48, c.x, 540);
  const std::size_t right = img.count(solid, c.x + 1, 48, 671, 540);
  CHECK(left > 2000);
  CHECK(right > 2000);
  CHECK(static_cast<double>(left) == Approx(static_cast<double>(right)).epsilon(0.1));
  // Nothing cut off at the frame's edges.
  CHECK(img.count(solid, 17, 48, 18, 540) == 0);
  CHECK(img.count(solid, 670, 48, 671, 540) == 0);
}

TEST_CASE("the section view colours each material apart and names it", "[unit][render]") {
  // Half a 40 mm plate whose x > 0 half is of a second material, written as a run writes it
  // (the scene's ids name the materials). x is up in the section: the second material (the
  // map's top, yellow) above the centre, the first (its bottom, purple) below; the legend
  // holds one swatch of each, in those colours, with its name beside it.
  unsetenv("DISPLAY");
  TempFolder dir("section_materials");
  RunSpec spec;
  spec.half = true;
  spec.plates.push_back({"plate", Vec3(-20 * mm, 0, -2 * mm), Vec3(40 * mm, 20 * mm, 2 * mm)});
  Model model = buildRun(spec);
  shapePlates(model, spec);
  model.materials.push_back(elasticMaterial());
  for (std::size_t e = 0; e < model.elems.size(); ++e) {
    double x = 0;
    for (int n : model.elems.conn[e]) x += 0.25 * model.nodes.x0[static_cast<std::size_t>(n)].x();
    model.elems.material[e] = x > 0 ? 1 : 0;
  }
  SeriesOptions series;
  series.material_names = {"steel_4340", "OFHC_copper"};
  SeriesWriter(dir.path, series).write(model, 10e-6);
  writeScene(dir.path, spec);
  const Image img = readPng(renderSectionView(dir.path.string(), -1, options800x600("material"),
                                              (dir.path / "section.png").string()));
  const Centre c = sceneCentre(img);
  CHECK(brightness(img.at(c.x, c.y + 100)) > 450);
  CHECK(brightness(img.at(c.x, c.y - 100)) < 300);
  // legend (render_detail::addLegend): swatches of 20 px from (684, 486) down, 30 px apart
  const unsigned char* first = img.at(694, 496);
  const unsigned char* second = img.at(694, 466);
  CHECK(brightness(first) < 300);
  CHECK(brightness(second) > 450);
  CHECK(colourDistance(first, img.at(c.x, c.y - 100)) < 40);
  CHECK(colourDistance(second, img.at(c.x, c.y + 100)) < 40);
  const auto ink = [](const unsigned char* p) { return brightness(p) < 300; };
  CHECK(img.count(ink, 712, 490, 799, 502) > 20);  // "steel_4340"
  CHECK(img.count(ink, 712, 460, 799, 472) > 20);  // "OFHC_copper"
}

TEST_CASE("a plate made of particles is drawn as its particles, coloured, with its hole",
          "[unit][render]") {
  // Reference: renderPlateImages (plate_images.hpp). A 40 x 40 x 2 mm plate of 1 mm^3
  // particles with a 12 mm hole, damage 0.3 and 100 MPa pressure for x < 0, 0.9 and 300 MPa
  // for x > 0. Its hole is found from its particles (findParticleHoles: the equivalent
  // diameter within a spacing, 1 mm, of the removed columns'); the debris is seen through it
  // in the front view, and the halves are coloured apart by damage and by pressure. The pressure is drawn
  // in the bar's MPa: in Pa, both halves lay beyond the range's top, one colour. The rear
  // view outlines the hole over the debris flying behind it. Strips of failed particles at
  // the plate's sides are its debris, not the plate.
  unsetenv("DISPLAY");
  TempFolder dir("plate_of_particles");
  RunSpec spec;
  auto plate = squarePlate("plate", 6 * mm, [](const Vec3& column, PointState& st) {
    st.damage = std::abs(column.x()) > 17 * mm ? 1.0 : column.x() < 0 ? 0.3 : 0.9;
    st.p = column.x() < 0 ? 100e6 : 300e6;
  });
  plate.particles = true;
  spec.plates.push_back(plate);
  // A cloud of debris 1.5 mm behind the plate over its hole and rim, which hides the hole's
  // outline from the rear camera unless the outline is drawn over the scene.
  for (int j = -8; j <= 8; ++j)
    for (int i = -8; i <= 8; ++i)
      if (std::hypot(i, j) <= 8) spec.particles.push_back(Vec3(i * mm, j * mm, -3.5 * mm));
  writePlateRun(dir.path, spec);
  for (const std::string field : {"damage", "pressure"}) {
    CAPTURE(field);
    const std::vector<PlateImages> images = renderPlateImages(
        dir.path.string(), -1, options800x600(field), (dir.path / field).string());
    REQUIRE(images.size() == 1);
    const PlateHoles& h = images[0].holes;
    REQUIRE(h.holes.size() == 1);
    CHECK(std::abs(h.holes[0].diameter - std::sqrt(4 * columnArea(6 * mm) / M_PI)) <= 1 * mm);
    CHECK(h.holes[0].centroid.head<2>().norm() < 0.1 * mm);
    const Image front = readPng(images[0].front_png);
    const Centre c = sceneCentre(front);
    CHECK(near(front.at(c.x, c.y), debrisColour(1).data(), 60));  // seen through the hole
    const int d = static_cast<int>(12.5 * mm / images[0].pixel_size);  // a particle's centre
    // The image's right is +x (u = v x n with v = y, n = z): the higher values, brighter.
    CHECK(!white(front.at(c.x - d, c.y)));
    CHECK(brightness(front.at(c.x + d, c.y)) > brightness(front.at(c.x - d, c.y)) + 60);
    // The failed strips (|x| > 17 mm) are the plate's debris, in its body's colour: a failed
    // particle's centre at (18.5, 0.5) mm.
    const unsigned char* failed = front.at(c.x + static_cast<int>(18.5 * mm / images[0].pixel_size),
                                           c.y + static_cast<int>(0.5 * mm / images[0].pixel_size));
    CHECK(near(failed, debrisColour(0).data(), 60));
    // The rear view: the hole's outline in red over the debris behind the plate (none of it
    // in view when drawn in the scene). Its 3-pixel line follows the particles' scalloped
    // edge, whose wiggles overlap at the pixel's scale: over half its length's pixels.
    const Image rear = readPng(images[0].rear_png);
    const unsigned char outline[3] = {227, 26, 28};
    const std::vector<Vec3>& loop = h.holes[0].outline;
    double perimeter = 0;
    for (std::size_t k = 0; k < loop.size(); ++k)
      perimeter += (loop[(k + 1) % loop.size()] - loop[k]).norm();
    const double line_px = 3 * perimeter / images[0].pixel_size;
    const auto red = [&](const unsigned char* p) { return near(p, outline, 40); };
    CHECK(static_cast<double>(rear.count(red)) > 0.5 * line_px);
  }
  // fesph compare measures the plate from its particles too: the hole, the plate's extent.
  const SimulatedPlate simulated = readSimulatedPlate(dir.path.string(), -1, 0, "plate", false);
  REQUIRE(simulated.holes.holes.size() == 1);
  CHECK(std::abs(simulated.holes.holes[0].diameter - std::sqrt(4 * columnArea(6 * mm) / M_PI)) <=
        1 * mm);
  // the unfailed part: centres to 16.5 mm off the middle, discs of sqrt(3) r = 0.87 mm
  CHECK(simulated.half_size.x() == Approx(17.37 * mm).margin(0.05 * mm));
  CHECK(simulated.half_size.y() == Approx(20 * mm).margin(1 * mm));
  // A body with neither elements nor particles there is named.
  CHECK_THROWS_WITH(readSimulatedPlate(dir.path.string(), -1, 7, "ghost", false),
                    Catch::Contains("plate 'ghost' has neither a live element nor a particle"));
}

TEST_CASE("particles take the field in the colour bar's units, or their body's colour",
          "[unit][render]") {
  // Reference: particleActor (plate_images.hpp), which the plate images and the section view
  // colour particles with. Pressure is drawn in MPa (fieldTitle): a particle at 250e6 Pa is
  // 250 on the bar; it was drawn at 250e6, beyond any bar's top. A field the particle series
  // lacks draws the particles in their body's colour, not as 0.
  vtkNew<vtkPolyData> particles;
  vtkNew<vtkPoints> points;
  points->InsertNextPoint(0, 0, 0);
  points->InsertNextPoint(1e-3, 0, 0);
  particles->SetPoints(points);
  const auto array = [&](const char* name, double a, double b) {
    vtkNew<vtkDoubleArray> values;
    values->SetName(name);
    values->InsertNextValue(a);
    values->InsertNextValue(b);
    particles->GetPointData()->AddArray(values);
  };
  array("radius", 0.5e-3, 0.5e-3);
  array("body", 1, 1);
  array("pressure", 250e6, -40e6);
  double unit = 0;
  render_detail::fieldTitle("pressure", &unit);
  const vtkSmartPointer<vtkLookupTable> lut = render_detail::viridis(-100, 300);
  // The points the actor draws (it owns them: keep it).
  const auto drawn = [](vtkActor* actor) {
    REQUIRE(actor);
    auto* mapper = vtkGlyph3DMapper::SafeDownCast(actor->GetMapper());
    REQUIRE(mapper);
    return vtkPolyData::SafeDownCast(mapper->GetInputDataObject(0, 0));
  };
  const vtkSmartPointer<vtkActor> coloured =
      render_detail::particleActor(particles, {0, 1}, lut, "pressure", unit);
  vtkDataArray* value = drawn(coloured)->GetPointData()->GetArray("value");
  REQUIRE(value);
  CHECK(value->GetTuple1(0) == Approx(250.0).epsilon(1e-12));
  CHECK(value->GetTuple1(1) == Approx(-40.0).epsilon(1e-12));
  const vtkSmartPointer<vtkActor> lacking =
      render_detail::particleActor(particles, {0, 1}, lut, "von_mises", unit);
  vtkPolyData* plain = drawn(lacking);
  CHECK(plain->GetPointData()->GetArray("value") == nullptr);
  vtkDataArray* colour = plain->GetPointData()->GetArray("colour");
  REQUIRE(colour);
  const std::array<unsigned char, 3> expected = debrisColour(1);
  for (int k = 0; k < 3; ++k) CHECK(colour->GetComponent(0, k) == expected[k]);
}
