// SPDX-License-Identifier: MIT
// `fesph compare` end to end: a run folder with a perforated plate written by SeriesWriter, a
// synthetic photograph of it written as PNG (and JPEG), the command run as a user would, and
// its report, images and data files checked.
#include "render/photo_compare.hpp"
#include "render/series_writer.hpp"

#include "core/common/error.hpp"
#include "core/mesh/structured_box.hpp"
#include "core/state/model_build.hpp"
#include "tests/render/png_image.hpp"
#include "tests/support/models.hpp"
#include "tests/support/command.hpp"
#include "tests/support/temp_folder.hpp"
#include "tests/support/text.hpp"

#include <catch2/catch.hpp>

#include <vtkImageData.h>
#include <vtkJPEGWriter.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>

#include <cmath>
#include <fstream>
#include <random>
#include <regex>

using namespace fesph;
using fesph::testing::Image;
using fesph::testing::readPng;
using fesph::testing::slurp;
using fesph::testing::TempFolder;
namespace fs = std::filesystem;

namespace {

constexpr double mm = 1e-3;

/// Body 0 "bullet" (projectile), body 1 "plate": 40 x 40 x 2 mm of 1 mm cubes centred on the
/// axis with the cube columns within 6 mm of (hx, hy) mm eroded; `half`: only its y >= 0 half,
/// as a half model (symmetry plane y = 0).
void writeRun(const fs::path& dir, double hx, double hy, bool half = false) {
  Model model;
  model.materials.push_back(testing::elasticMaterial());
  Placement behind;
  behind.translation = Vec3(-2 * mm, -2 * mm, 10 * mm);
  addBody(model, "bullet", structuredBox(Vec3::Zero(), Vec3(4 * mm, 4 * mm, 4 * mm), 2, 2, 2), 0,
          behind, Vec3(0, 0, -300), true);
  addBody(model, "plate",
          half ? structuredBox(Vec3(-20 * mm, 0, -2 * mm), Vec3(40 * mm, 20 * mm, 2 * mm), 40, 20, 2)
               : structuredBox(Vec3(-20 * mm, -20 * mm, -2 * mm), Vec3(40 * mm, 40 * mm, 2 * mm), 40, 40, 2),
          0, Placement{}, Vec3::Zero(), false);
  finaliseModel(model);
  const Body& plate = model.bodies[1];
  for (std::size_t e = plate.elem_begin; e < plate.elem_end; ++e) {
    Vec3 c = Vec3::Zero();
    for (int n : model.elems.conn[e]) c += 0.25 * model.nodes.x[n];
    const double cx = std::floor(c.x() / mm) + 0.5, cy = std::floor(c.y() / mm) + 0.5;
    if (std::hypot(cx - hx, cy - hy) < 6) model.elems.status[e] = ElemStatus::Eroded;
  }
  SeriesWriter(dir).write(model, 20e-6);
  std::ofstream(dir / "scene.toml") << (half ? "[simulation]\nsymmetry = \"half\"\n" : "")
                                    << "[[bodies]]\nname = \"bullet\"\nprojectile = true\n"
                                       "[[bodies]]\nname = \"plate\"\n";
}

struct Disc {
  double x, y, r;  ///< mm
};

/// Photograph of the front face at 0.08 mm/px, the plate's centre at pixel (centre): a plate lit
/// from 0.55 (left) to 0.75 (right) on a dark background, with holes where the 1 mm columns'
/// centres lie in one of `holes`, blurred and noisy.
GrayImage photograph(Eigen::Vector2d centre, const std::vector<Disc>& holes) {
  const int w = 640, h = 560;
  GrayImage ideal{w, h, std::vector<float>(static_cast<std::size_t>(w) * h)};
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      const double a = (i + 0.5 - centre.x()) * 0.08, b = -(j + 0.5 - centre.y()) * 0.08;
      const double ca = std::floor(a) + 0.5, cb = std::floor(b) + 0.5;
      bool plate = std::abs(a) < 20 && std::abs(b) < 20;
      for (const Disc& d : holes) plate = plate && std::hypot(ca - d.x, cb - d.y) >= d.r;
      ideal.value[static_cast<std::size_t>(j) * w + i] =
          static_cast<float>(plate ? 0.55 + 0.2 * i / w : 0.1);
    }
  GrayImage photo = ideal;
  std::mt19937 rng(7);
  const auto uniform = [&] { return (rng() + 0.5) / 4294967296.0; };
  for (int j = 0; j < h; ++j)
    for (int i = 0; i < w; ++i) {
      double s = 0;
      for (int dj = -1; dj <= 1; ++dj)
        for (int di = -1; di <= 1; ++di)
          s += ideal.at(std::clamp(i + di, 0, w - 1), std::clamp(j + dj, 0, h - 1));
      const double noise = 0.04 * std::sqrt(-2 * std::log(uniform())) * std::cos(2 * M_PI * uniform());
      photo.value[static_cast<std::size_t>(j) * w + i] = static_cast<float>(std::clamp(s / 9 + noise, 0.0, 1.0));
    }
  return photo;
}

/// The photograph of the plate writeRun(hx, hy) makes: one hole of radius 6 mm at (hx, hy) mm.
GrayImage photograph(Eigen::Vector2d centre, double hx, double hy) {
  return photograph(centre, {{hx, hy, 6}});
}

using Result = fesph::testing::CommandResult;

Result runFesph(const std::string& args) {
  return fesph::testing::runCommand(std::string(FESPH_BINARY) + " " + args + " 2>&1");
}

double jsonNumber(const std::string& json, const std::string& key) {
  std::smatch m;
  if (!std::regex_search(json, m, std::regex("\"" + key + "\": ([-0-9.eE+]+)"))) return NAN;
  return std::stod(m[1]);
}


}  // namespace

TEST_CASE("fesph compare: matching and shifted photographs of a perforated plate", "[unit][render]") {
  unsetenv("DISPLAY");
  TempFolder dir("compare");
  writeRun(dir.path / "run", 0, 0);
  const Eigen::Vector2d centre(330.0, 270.0);
  writeGrayPng(photograph(centre, 0, 0), (dir.path / "match.png").string());
  writeGrayPng(photograph(centre, 8, 0), (dir.path / "shifted.png").string());
  const std::string run = (dir.path / "run").string();
  const std::string base = run + " --plate 1 --mm-per-px 0.08 --center 330,270";

  {  // the matching photograph
    const Result r = runFesph("compare " + base + " --image " + (dir.path / "match.png").string());
    INFO(r.out);
    REQUIRE(r.code == 0);
    CHECK(r.out.find("photograph: 1 hole") != std::string::npos);
    CHECK(r.out.find("simulation: 1 hole") != std::string::npos);
    CHECK(r.out.find("(Otsu)") != std::string::npos);
    const fs::path out = dir.path / "run" / "compare";
    const std::string json = slurp(out / "plate_compare.json");
    CHECK(jsonNumber(json, "iou") >= 0.9);
    // The photograph's hole: the 112 removed columns of 1 mm^2, within 3 %.
    CHECK(jsonNumber(json, "area_m2") == Approx(112e-6).epsilon(0.03));
    const std::string csv = slurp(out / "plate_compare.csv");
    CHECK(csv.rfind("source,hole,area_m2,diameter_m,centroid_u_m,centroid_v_m,overlaps,"
                    "nearest_other_m\nphoto,1,", 0) == 0);
    CHECK(csv.find("\nsimulation,1,") != std::string::npos);
    // Hole by hole: the one hole of each side overlaps the other's.
    CHECK(r.out.find("photograph 1 + simulation 1  overlap") != std::string::npos);
    CHECK(r.out.find("paired: 1 of 1 photographed hole, 1 of 1 simulated") != std::string::npos);
    CHECK(json.find("\"pairs\": [{\"photo\": 1, \"simulation\": 1, \"overlap_m2\": ") !=
          std::string::npos);
    CHECK(json.find("\"overlaps\": [1], \"nearest_other_m\": ") != std::string::npos);
    // The CSV's row: area, diameter, centroid, then the partner (simulated hole 1) and the
    // distance to it.
    CHECK(std::regex_search(csv, std::regex("\nphoto,1,([^,\n]*,){4}1,[-0-9.e]+\n")));
    // Each row the figures of its own source: the CSV's areas are the JSON's, digit for digit
    // (written alike), and the two holes' areas differ.
    const auto csvArea = [&](const std::string& source) {
      const std::size_t at = csv.find("\n" + source + ",1,") + source.size() + 4;
      return csv.substr(at, csv.find(',', at) - at);
    };
    const auto jsonArea = [&](const std::string& list) {
      const std::size_t key = json.find("\"area_m2\": ", json.find("\"" + list + "\"")) + 11;
      return json.substr(key, json.find(',', key) - key);
    };
    CHECK(csvArea("simulation") == jsonArea("simulation_holes"));
    CHECK(csvArea("photo") == jsonArea("photo_holes"));
    CHECK(csvArea("photo") != csvArea("simulation"));

    // Side by side is two photographs wide. Its right half: the simulated hole filled dark
    // (~17.5k pixels of 112 mm^2 at 0.08 mm per pixel) inside a blue outline two pixels wide
    // (~2 x 470 pixels round it).
    const Image side = readPng((out / "plate_compare_side.png").string());
    CHECK(side.width > 2 * 640);
    CHECK(side.height == 560);
    const int right = side.width - 640;
    const std::size_t dark =
        side.count([](const unsigned char* p) { return p[0] < 40 && p[1] < 40 && p[2] < 40; }, right);
    const std::size_t blue =
        side.count([](const unsigned char* p) { return p[2] > 200 && p[0] < 80 && p[1] < 160; }, right);
    CHECK(dark > 12000);
    CHECK(blue > 500);
    CHECK(blue < 3000);
    // The overlay is green at the plate's centre, in the hole (rows from the bottom here).
    const Image overlay = readPng((out / "plate_compare_overlay.png").string());
    const unsigned char* px = overlay.at(330, 560 - 1 - 270);
    CHECK(int(px[1]) > int(px[0]) + 60);
  }
  {  // the hole 8 mm off, as a JPEG
    const GrayImage shifted = photograph(centre, 8, 0);
    vtkNew<vtkImageData> img;
    img->SetDimensions(shifted.width, shifted.height, 1);
    img->AllocateScalars(VTK_UNSIGNED_CHAR, 1);
    for (int j = 0; j < shifted.height; ++j)
      for (int i = 0; i < shifted.width; ++i)
        *static_cast<unsigned char*>(img->GetScalarPointer(i, shifted.height - 1 - j, 0)) =
            static_cast<unsigned char>(255 * shifted.at(i, j) + 0.5);
    vtkNew<vtkJPEGWriter> jpeg;
    jpeg->SetInputData(img);
    jpeg->SetQuality(90);
    jpeg->SetFileName((dir.path / "shifted.jpg").c_str());
    jpeg->Write();
    const Result r = runFesph("compare " + base + " --image " + (dir.path / "shifted.jpg").string() +
                           " --out " + (dir.path / "out").string());
    INFO(r.out);
    REQUIRE(r.code == 0);
    // Discs of 6 mm radius 8 mm apart: a lens of 24.8 mm^2 over a union of 201 mm^2, IoU 0.12.
    const double iou = jsonNumber(slurp(dir.path / "out" / "plate_compare.json"), "iou");
    CHECK(iou < 0.5);
    CHECK(iou == Approx(0.12).margin(0.03));
    // The overlay tints each side's own part: the photograph's hole alone red, the
    // simulation's alone blue (each disc less the lens: ~14k pixels at 0.08 mm per pixel).
    {
      const Image overlay = readPng((dir.path / "out" / "plate_compare_overlay.png").string());
      CHECK(overlay.count([](const unsigned char* p) { return p[0] > p[1] + 60 && p[0] > p[2] + 60; }) >
            10000);
      CHECK(overlay.count([](const unsigned char* p) { return p[2] > p[0] + 60 && p[2] > p[1] + 30; }) >
            10000);
    }
    // Without --center the holes are aligned, and the offset shows in the centroid.
    const Result a = runFesph("compare " + run + " --mm-per-px 0.08 --image " +
                           (dir.path / "shifted.png").string() + " --out " + (dir.path / "auto").string());
    REQUIRE(a.code == 0);
    CHECK(jsonNumber(slurp(dir.path / "auto" / "plate_compare.json"), "iou") >= 0.9);
    CHECK(a.out.find("largest holes' centroids aligned") != std::string::npos);
    CHECK(slurp(dir.path / "auto" / "plate_compare.json").find("\"face\": \"front\"") !=
          std::string::npos);
    // A photograph written as NAME.png and compared into the folder NAME.
    const auto comparePhoto = [&](const GrayImage& photo, const std::string& name) {
      const std::string png = (dir.path / (name + ".png")).string();
      writeGrayPng(photo, png);
      return runFesph("compare " + base + " --image " + png + " --out " + (dir.path / name).string());
    };
    // A hole 14.1 mm off (at (-10, -10) mm), clear of the simulated one: no pair, each hole on
    // its own side, the other's nearest centroid 14.14 mm away.
    const Result apart = comparePhoto(photograph(centre, -10, -10), "apart");
    INFO(apart.out);
    REQUIRE(apart.code == 0);
    CHECK(apart.out.find("paired: 0 of 1 photographed hole, 0 of 1 simulated") != std::string::npos);
    CHECK(apart.out.find("    simulation 1 only  nearest photographed hole ") != std::string::npos);
    std::smatch m;
    REQUIRE(std::regex_search(apart.out, m, std::regex("photograph 1 only  nearest simulated hole ([0-9.]+) mm")));
    CHECK(std::stod(m[1]) == Approx(std::hypot(10.0, 10.0)).margin(0.1));
    const std::string apart_csv = slurp(dir.path / "apart" / "plate_compare.csv");
    CHECK(apart_csv.find("\nphoto,1,") != std::string::npos);
    CHECK(apart_csv.find(",,0.014") != std::string::npos);  // no partner, the nearest in m
    CHECK(slurp(dir.path / "apart" / "plate_compare.json").find("\"pairs\": []") != std::string::npos);
    // Two 3 mm holes 4 mm either side of the centre, both inside the simulated 6 mm one: two
    // pairs, every hole of both sides paired.
    const Result two = comparePhoto(photograph(centre, {{-4, 0, 3}, {4, 0, 3}}), "two");
    INFO(two.out);
    REQUIRE(two.code == 0);
    CHECK(two.out.find("photograph: 2 holes") != std::string::npos);
    CHECK(two.out.find("paired: 2 of 2 photographed holes, 1 of 1 simulated") != std::string::npos);
    // A photograph of the rear face: the JSON says which face it was compared as.
    const Result rear = runFesph("compare " + run + " --face rear --mm-per-px 0.08 --image " +
                                 (dir.path / "shifted.png").string() + " --out " +
                                 (dir.path / "rear").string());
    REQUIRE(rear.code == 0);
    CHECK(slurp(dir.path / "rear" / "plate_compare.json").find("\"face\": \"rear\"") !=
          std::string::npos);
  }
  {  // bad input gets a clear error and exit code 2
    const std::string photo = " --image " + (dir.path / "match.png").string();
    Result r = runFesph("compare " + run + " --plate 3 --mm-per-px 0.08" + photo);
    CHECK(r.code == 2);
    CHECK(r.out.find("no such plate; the run has 1 = 'plate'") != std::string::npos);
    std::ofstream(dir.path / "not_an_image.png") << "hello";
    r = runFesph("compare " + base + " --image " + (dir.path / "not_an_image.png").string());
    CHECK(r.code == 2);
    CHECK(r.out.find("not_an_image.png") != std::string::npos);
    r = runFesph("compare " + run + " --mm-per-px 0.08 --center 12" + photo);
    CHECK(r.code == 2);
    CHECK(r.out.find("--center must be X,Y") != std::string::npos);
    // A threshold splits the brightness (0, 1): at 0 or 1 every pixel is plate, or hole. CLI11's
    // range took both ends and said "Value 2 not in range 0.000000 to 1.000000".
    for (const char* t : {"0", "1", "2", "-0.5", "abc", "nan"}) {
      r = runFesph("compare " + run + " --mm-per-px 0.08 --threshold " + t + photo);
      INFO(r.out);
      CHECK(r.code == 2);
      CHECK(r.out.find(std::string("--threshold: expected a number in (0, 1), got ") + t) !=
            std::string::npos);
    }
  }
}

TEST_CASE("fesph compare: a half model is compared as the full plate", "[unit][render]") {
  unsetenv("DISPLAY");
  TempFolder dir("compare_half");
  writeRun(dir.path / "run", 0, 0, true);
  const Eigen::Vector2d centre(330.0, 270.0);
  writeGrayPng(photograph(centre, 0, 0), (dir.path / "match.png").string());
  const Result r = runFesph("compare " + (dir.path / "run").string() +
                            " --mm-per-px 0.08 --center 330,270 --image " + (dir.path / "match.png").string());
  INFO(r.out);
  REQUIRE(r.code == 0);
  // The hole cut by the symmetry plane is one full hole of the 112 removed columns.
  CHECK(r.out.find("simulation: 1 hole") != std::string::npos);
  const std::string json = slurp(dir.path / "run" / "compare" / "plate_compare.json");
  CHECK(jsonNumber(json, "iou") >= 0.9);
  std::smatch m;
  REQUIRE(std::regex_search(json, m, std::regex("simulation_holes\": \\[\\{\"area_m2\": ([-0-9.eE+]+)")));
  CHECK(std::stod(m[1]) == Approx(112e-6).epsilon(0.02));
}

TEST_CASE("photographs: colour is read as luma, rows from the top, 16-bit scaled", "[unit][render]") {
  TempFolder dir("photo_read");
  for (const int type : {VTK_UNSIGNED_CHAR, VTK_UNSIGNED_SHORT}) {
    const double full = type == VTK_UNSIGNED_CHAR ? 255 : 65535;
    vtkNew<vtkImageData> img;
    img->SetDimensions(4, 3, 1);
    img->AllocateScalars(type, 3);
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 4; ++x) {
        img->SetScalarComponentFromDouble(x, y, 0, 0, y == 2 ? full : 0);        // red top row
        img->SetScalarComponentFromDouble(x, y, 0, 1, x == 1 ? full : 0);        // green column
        img->SetScalarComponentFromDouble(x, y, 0, 2, std::round(0.5 * full));
      }
    const std::string path = (dir.path / ("rgb" + std::to_string(type) + ".png")).string();
    vtkNew<vtkPNGWriter> writer;
    writer->SetInputData(img);
    writer->SetFileName(path.c_str());
    writer->Write();
    const GrayImage g = readPhoto(path);
    REQUIRE(g.width == 4);
    REQUIRE(g.height == 3);
    const double blue = 0.114 * std::round(0.5 * full) / full;
    CHECK(g.at(0, 0) == Approx(0.299 + blue).margin(1e-6));  // VTK's top row is row 0 here
    CHECK(g.at(1, 2) == Approx(0.587 + blue).margin(1e-6));
    CHECK(g.at(2, 1) == Approx(blue).margin(1e-6));
  }
  CHECK_THROWS_AS(readPhoto((dir.path / "missing.png").string()), InputError);
}
