// SPDX-License-Identifier: MIT
// Off-screen images with DISPLAY unset: a synthetic perforated plate written with SeriesWriter
// and rendered back (pixels, hole area at the known scale), the section view, and a velocity
// plot of two synthetic histories (pixels of each curve colour).
#include "render/plate_images.hpp"
#include "render/section_view.hpp"
#include "render/series_writer.hpp"
#include "render/velocity_plot.hpp"

#include "core/common/error.hpp"
#include "core/mesh/structured_box.hpp"
#include "tests/support/models.hpp"

#include "tests/render/png_image.hpp"
#include "tests/support/temp_folder.hpp"

#include <catch2/catch.hpp>

#include <vtkDoubleArray.h>
#include <vtkIntArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataWriter.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <unistd.h>

using namespace fesph;
using namespace fesph::testing;
namespace fs = std::filesystem;

namespace {

constexpr double mm = 1e-3;

/// A run folder: body 0 "bullet" (projectile, 4 x 4 x 10 mm, behind the plate), body 1
/// "plate" (40 x 40 x 2 mm of 1 mm cubes, front face z = 0) with the cube columns whose centre
/// is within 6 mm of the axis eroded; damage falls off with the distance from the hole; a few
/// bullet particles lie on the plate's front face near a corner. Returns the true hole area.
double writeRun(const fs::path& dir) {
  Model model;
  model.materials.push_back(testing::elasticMaterial());
  Placement behind;
  behind.translation = Vec3(-2 * mm, -2 * mm, -20 * mm);
  addBody(model, "bullet", structuredBox(Vec3::Zero(), Vec3(4 * mm, 4 * mm, 10 * mm), 2, 2, 5), 0,
          behind, Vec3(0, 0, -300), true);
  addBody(model, "plate", structuredBox(Vec3(-20 * mm, -20 * mm, -2 * mm), Vec3(40 * mm, 40 * mm, 2 * mm), 40, 40, 2),
          0, Placement{}, Vec3::Zero(), false);
  finaliseModel(model);

  const double radius = 6 * mm;
  double true_area = 0;
  for (int j = 0; j < 40; ++j)
    for (int i = 0; i < 40; ++i)
      if (std::hypot(-19.5 + i, -19.5 + j) < 6) true_area += mm * mm;
  const Body& plate = model.bodies[1];
  for (std::size_t e = plate.elem_begin; e < plate.elem_end; ++e) {
    Vec3 c = Vec3::Zero();
    for (int n : model.elems.conn[e]) c += 0.25 * model.nodes.x[n];
    const double cx = (std::floor(c.x() / mm) + 0.5) * mm, cy = (std::floor(c.y() / mm) + 0.5) * mm;
    const double r = std::hypot(cx, cy);
    if (r < radius) model.elems.status[e] = ElemStatus::Eroded;
    model.elems.state[e].damage = std::exp(-(r - radius) / (4 * mm));
    model.elems.state[e].eps_p = 0.8 * std::exp(-(r - radius) / (3 * mm));
  }
  SeriesWriter(dir).write(model, 25e-6);

  // Particle series: five bullet particles of 0.6 mm radius near the corner (15, 15) mm,
  // replacing the (empty) particle series SeriesWriter wrote.
  vtkNew<vtkPolyData> particles;
  vtkNew<vtkPoints> pts;
  vtkNew<vtkDoubleArray> rad, eps;
  vtkNew<vtkIntArray> body;
  rad->SetName("radius");
  eps->SetName("plastic_strain");
  body->SetName("body");
  for (int k = 0; k < 5; ++k) {
    pts->InsertNextPoint((14 + k) * mm, 15 * mm, 0.7 * mm);
    rad->InsertNextValue(0.6 * mm);
    eps->InsertNextValue(0.5);
    body->InsertNextValue(0);
  }
  particles->SetPoints(pts);
  particles->GetPointData()->AddArray(rad);
  particles->GetPointData()->AddArray(eps);
  particles->GetPointData()->AddArray(body);
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(particles);
  writer->SetFileName((dir / "bullet_000000.vtp").c_str());
  writer->Write();
  PvdCollection(dir / "particles.pvd", false).add(25e-6, "bullet_000000.vtp");

  std::ofstream(dir / "scene.toml") << "[[bodies]]\nname = \"bullet\"\nprojectile = true\n"
                                       "[[bodies]]\nname = \"plate\"\n";
  return true_area;
}

void writeHistory(const fs::path& path, double v0, double v_residual) {
  std::ofstream out(path);
  out << "time,step,dt,kinetic,bullet_vx,bullet_vy,bullet_vz\n";
  for (int i = 0; i <= 100; ++i) {
    const double t = i * 0.5e-6;
    const double v = v_residual + (v0 - v_residual) / (1 + std::exp((t - 20e-6) / 3e-6));
    out << t << ',' << i << ",1e-9,0,0,0," << -v << '\n';
  }
}

}  // namespace

TEST_CASE("plate images render headless and show the hole at the right scale", "[unit][render]") {
  unsetenv("DISPLAY");  // prove that no X server is needed
  TempFolder dir("plate");
  const double true_area = writeRun(dir.path);
  ImageOptions options;
  options.width = 800;
  options.height = 600;
  const std::vector<PlateImages> images =
      renderPlateImages(dir.path.string(), -1, options, (dir.path / "images").string());

  REQUIRE(images.size() == 1);  // the bullet is the projectile: only the plate is drawn
  const PlateImages& plate = images[0];
  CHECK(plate.plate == "plate");
  CHECK(plate.time == Approx(25e-6));
  REQUIRE(plate.holes.holes.size() == 1);
  CHECK(plate.holes.holes[0].area == Approx(true_area).epsilon(0.02));

  const Image front = readPng(plate.front_png);
  REQUIRE(front.width == 800);
  REQUIRE(front.height == 600);
  const std::size_t pixels = static_cast<std::size_t>(front.width) * front.height;
  CHECK(front.count([](const unsigned char* p) { return !white(p); }) > pixels / 5);

  // Hole area from pixels: white pixels inside the plate's square, at pixel_size m per pixel.
  const double cx = 0.5 * (render_detail::kSceneViewport[0] + render_detail::kSceneViewport[2]) * 800;
  const double cy = 0.5 * (render_detail::kSceneViewport[1] + render_detail::kSceneViewport[3]) * 600;
  const int half = static_cast<int>(17 * mm / plate.pixel_size);
  const std::size_t hole_px = front.count(white, static_cast<int>(cx) - half, static_cast<int>(cy) - half,
                                          static_cast<int>(cx) + half, static_cast<int>(cy) + half);
  CHECK(hole_px * plate.pixel_size * plate.pixel_size == Approx(true_area).epsilon(0.05));

  // The bullet particles on the front face are drawn in the bullet's colour.
  double c[3];
  render_detail::bodyColour(0, c);
  const unsigned char red[3] = {static_cast<unsigned char>(255 * c[0]),
                                static_cast<unsigned char>(255 * c[1]),
                                static_cast<unsigned char>(255 * c[2])};
  CHECK(front.count([&](const unsigned char* p) { return near(p, red, 60); }) > 50);

  // The rear view has the hole outline in red, the whole of its 3-pixel line in view (drawn
  // on the rear face's side of the plate, not hidden by it).
  const Image rear = readPng(plate.rear_png);
  const unsigned char outline[3] = {227, 26, 28};
  const std::vector<Vec3>& loop = plate.holes.holes[0].outline;
  double perimeter = 0;
  for (std::size_t k = 0; k < loop.size(); ++k) perimeter += (loop[(k + 1) % loop.size()] - loop[k]).norm();
  const double line_px = 3 * perimeter / plate.pixel_size;
  const double red_px = static_cast<double>(rear.count([&](const unsigned char* p) { return near(p, outline, 40); }));
  CHECK(red_px > 0.8 * line_px);
  CHECK(red_px < 1.25 * line_px);
}

TEST_CASE("section view renders the y = 0 cut", "[unit][render]") {
  unsetenv("DISPLAY");
  TempFolder dir("section");
  writeRun(dir.path);
  ImageOptions options;
  options.width = 800;
  options.height = 600;
  const std::string png = renderSectionView(dir.path.string(), -1, options, (dir.path / "section.png").string());
  const Image img = readPng(png);
  CHECK(img.count([](const unsigned char* p) { return !white(p); }) > 800u * 600u / 20);
}

TEST_CASE("velocity plot draws one curve per run", "[unit][render]") {
  unsetenv("DISPLAY");
  TempFolder dir("plot");
  fs::create_directories(dir.path / "a");
  fs::create_directories(dir.path / "b");
  writeHistory(dir.path / "a" / "history.csv", 800, 520);
  writeHistory(dir.path / "b" / "history.csv", 800, 430);
  ImageOptions options;
  options.width = 900;
  options.height = 600;
  const std::string png = renderVelocityPlot(
      {{"run A", (dir.path / "a" / "history.csv").string()}, {"run B", (dir.path / "b" / "history.csv").string()}},
      "bullet", (dir.path / "velocity.png").string(), options);
  const Image img = readPng(png);
  for (int k = 0; k < 2; ++k) {
    unsigned char c[3];
    curveColour(k, c);
    CHECK(img.count([&](const unsigned char* p) { return near(p, c, 30); }) > 300);
  }
  // Velocity from 0: a curve's heights above the time axis are in the ratio of its velocities
  // (run B: 800 m/s at the start, 430 at the end). The axis: the longest dark row.
  int axis_y = 0, axis_run = 0;
  for (int y = 0; y < img.height / 2; ++y) {
    const int run = static_cast<int>(img.count(
        [](const unsigned char* p) { return p[0] < 80 && p[1] < 80 && p[2] < 80; }, 0, y,
        img.width - 1, y));
    if (run > axis_run) axis_run = run, axis_y = y;
  }
  REQUIRE(axis_run > img.width / 2);
  unsigned char b[3];
  curveColour(1, b);
  std::vector<std::pair<int, int>> curve;  // (x, y) of run B's pixels
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (near(img.at(x, y), b, 30)) curve.emplace_back(x, y);
  REQUIRE(!curve.empty());
  int x_first = img.width;
  for (const auto& [x, y] : curve) x_first = std::min(x_first, x);
  // Mean height of the pixels with x in [x0, x1] and y below y_max.
  const auto meanHeight = [&](int x0, int x1, int y_max) {
    double sum = 0, n = 0;
    for (const auto& [x, y] : curve)
      if (x >= x0 && x <= x1 && y < y_max) sum += y - axis_y, n += 1;
    return n > 0 ? sum / n : 0.0;
  };
  const double start = meanHeight(x_first, x_first + img.width / 30, img.height);
  // The end: the rightmost pixels below 70 % of the start's height (the legend's sample of
  // the colour sits at the top).
  const int y_cut = axis_y + static_cast<int>(0.7 * start);
  int x_last = 0;
  for (const auto& [x, y] : curve)
    if (y < y_cut) x_last = std::max(x_last, x);
  const double end = meanHeight(x_last - img.width / 30, x_last, y_cut);
  REQUIRE(end > 0);
  CHECK(start / end == Approx(800.0 / 430.0).epsilon(0.03));
  // The velocity axis: the longest dark column, from the time axis up. It ends 8 % above the
  // highest velocity, so that the curve's start does not run along the frame.
  int axis_x = 0, axis_top = 0, longest = 0;
  for (int x = 0; x < img.width / 2; ++x) {
    int run = 0, top = 0;
    for (int y = axis_y; y < img.height; ++y) {
      const unsigned char* p = img.at(x, y);
      if (!(p[0] < 80 && p[1] < 80 && p[2] < 80)) break;
      ++run, top = y;
    }
    if (run > longest) longest = run, axis_x = x, axis_top = top;
  }
  INFO("velocity axis at x = " << axis_x);
  CHECK(start / (axis_top - axis_y) == Approx(800.0 / (1.08 * 800.0)).epsilon(0.02));
  CHECK_THROWS_AS(renderVelocityPlot({{"x", (dir.path / "a" / "history.csv").string()}}, "nobody",
                                     (dir.path / "bad.png").string(), options),
                  RunError);
}

TEST_CASE("velocity plot draws a curve per projectile of a run that has several", "[unit][render]") {
  // A tandem shot: two projectiles, a lead slowed from 800 to 430 m/s and a follower at
  // 600 m/s throughout. Drawn with the body left open, both are curves of their own; with the
  // scene naming one projectile, one curve only.
  unsetenv("DISPLAY");
  TempFolder dir("plot_projectiles");
  const fs::path csv = dir.path / "history.csv";
  {
    std::ofstream out(csv);
    out << "time,step,dt,kinetic,plate_vx,plate_vy,plate_vz,lead_vx,lead_vy,lead_vz,"
           "follower_vx,follower_vy,follower_vz\n";
    for (int i = 0; i <= 100; ++i) {
      const double t = i * 0.5e-6;
      const double v = 430 + 370 / (1 + std::exp((t - 20e-6) / 3e-6));
      out << t << ',' << i << ",1e-9,0,0,0,0,0,0," << -v << ",0,0,-600\n";
    }
  }
  const auto scene = [&](bool both) {
    std::ofstream(dir.path / "scene.toml")
        << "[[bodies]]\nname = \"plate\"\n[[bodies]]\nname = \"lead\"\nprojectile = true\n"
        << "[[bodies]]\nname = \"follower\"\nprojectile = " << (both ? "true" : "false") << "\n";
  };
  ImageOptions options;
  options.width = 900;
  options.height = 600;
  unsigned char c[2][3];
  curveColour(0, c[0]);
  curveColour(1, c[1]);
  scene(true);
  CHECK(render_detail::plottedBodies(csv.string()) == std::vector<std::string>{"lead", "follower"});
  Image img = readPng(renderVelocityPlot({{"tandem", csv.string()}}, "", (dir.path / "both.png").string(), options));
  for (int k = 0; k < 2; ++k) {
    INFO("curve " << k);
    CHECK(img.count([&](const unsigned char* p) { return near(p, c[k], 30); }) > 300);
  }
  scene(false);
  CHECK(render_detail::plottedBodies(csv.string()) == std::vector<std::string>{"lead"});
  img = readPng(renderVelocityPlot({{"tandem", csv.string()}}, "", (dir.path / "one.png").string(), options));
  CHECK(img.count([&](const unsigned char* p) { return near(p, c[0], 30); }) > 300);
  CHECK(img.count([&](const unsigned char* p) { return near(p, c[1], 30); }) < 20);
}

TEST_CASE("velocity histories are read for the projectile, in microseconds", "[unit][render]") {
  TempFolder dir("velocity_read");
  const fs::path csv = dir.path / "history.csv";
  {
    std::ofstream out(csv);
    out << "time,step,dt,kinetic,plate_vx,plate_vy,plate_vz,bullet_vx,bullet_vy,bullet_vz\n"
        << "0,0,1e-9,0,0,0,0,30,40,-1200\n"
        << "1e-06,1,1e-9,0,1,2,-2,0,0,-900\n"
        << "2e-06,2,1e-9,0,0\n";  // cut short by a stopped run
  }
  using render_detail::readVelocity;
  // Without scene.toml: the history's first body.
  CHECK(readVelocity(csv.string(), "", VelocityMeasure::MinusVz).v ==
        std::vector<double>{0.0, 2.0});
  // With it: its projectile, though it is not the first body.
  std::ofstream(dir.path / "scene.toml") << "[[bodies]]\nname = \"plate\"\n"
                                            "[[bodies]]\nname = \"bullet\"\nprojectile = true\n";
  const render_detail::VelocitySeries speed = readVelocity(csv.string(), "", VelocityMeasure::Speed);
  CHECK(speed.t_us == std::vector<double>{0.0, 1.0});
  REQUIRE(speed.v.size() == 2);
  CHECK(speed.v[0] == Approx(std::sqrt(30.0 * 30 + 40 * 40 + 1200 * 1200)));
  CHECK(speed.v[1] == Approx(900));
  CHECK(readVelocity(csv.string(), "", VelocityMeasure::MinusVz).v ==
        std::vector<double>{1200.0, 900.0});
  CHECK(readVelocity(csv.string(), "plate", VelocityMeasure::Speed).v[1] == Approx(3));
  CHECK_THROWS_AS(readVelocity(csv.string(), "nobody", VelocityMeasure::Speed), RunError);
  CHECK_THROWS_AS(readVelocity((dir.path / "missing.csv").string(), "", VelocityMeasure::Speed),
                  RunError);
}
