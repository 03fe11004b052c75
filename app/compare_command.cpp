// SPDX-License-Identifier: MIT
// `fesph compare`: the holes in a photograph of a tested plate against the simulated plate of a
// run: hole count, areas, equivalent diameters, intersection-over-union, and the images.
#include "app/cli_checks.hpp"
#include "app/commands.hpp"

#include "core/common/error.hpp"
#include "render/photo_compare.hpp"
#include "render/plate_images.hpp"

#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <stdexcept>

namespace fesph {

namespace fs = std::filesystem;

int plateBody(const RunInfo& info, const std::string& which) {
  std::vector<int> plates;
  std::string names;
  for (std::size_t b = 0; b < info.bodies.size(); ++b) {
    if (info.bodies[b].projectile) continue;
    plates.push_back(static_cast<int>(b));
    names += (names.empty() ? "" : ", ") + std::to_string(plates.size()) + " = '" +
             info.bodies[b].name + "'";
  }
  for (int b : plates)
    if (info.bodies[b].name == which) return b;
  if (!which.empty() && which.find_first_not_of("0123456789") == std::string::npos) {
    const std::size_t n = std::stoul(which);
    if (n >= 1 && n <= plates.size()) return plates[n - 1];
  }
  throw std::invalid_argument("plate " + which + ": no such plate; the run has " +
                              (names.empty() ? std::string("none") : names));
}

namespace {

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

void printHoles(const char* what, const std::vector<HoleSize>& holes) {
  std::printf("  %s: %zu hole%s\n", what, holes.size(), holes.size() == 1 ? "" : "s");
  for (std::size_t k = 0; k < holes.size(); ++k)
    std::printf("    %2zu  area %9.3f mm2  equivalent diameter %7.3f mm  centroid (%.2f, %.2f) mm\n",
                k + 1, holes[k].area * 1e6, holes[k].diameter * 1e3, holes[k].centroid.x() * 1e3,
                holes[k].centroid.y() * 1e3);
}

/// Hole by hole: the overlapping pairs, then the holes of one side only with the distance to
/// the other side's nearest hole (a fragment hole the simulation put a few mm off, or none).
void printPairs(const HoleComparison& c) {
  std::printf("  hole by hole (holes that overlap are paired):\n");
  for (const HolePair& p : c.pairs) {
    const HoleSize &a = c.photo[p.photo], &b = c.simulated[p.simulated];
    std::printf("    photograph %zu + simulation %zu  overlap %.3f mm2  IoU %.3f  centroids %.2f mm "
                "apart  diameter %.3f / %.3f mm\n",
                p.photo + 1, p.simulated + 1, p.overlap * 1e6, p.iou,
                (a.centroid - b.centroid).norm() * 1e3, a.diameter * 1e3, b.diameter * 1e3);
  }
  std::size_t paired[2] = {0, 0};
  for (int side = 0; side < 2; ++side) {
    const bool photo = side == 0;
    const std::size_t n = (photo ? c.photo : c.simulated).size();
    for (std::size_t k = 0; k < n; ++k) {
      if (!partnersOf(c, k, photo).empty()) {
        ++paired[side];
        continue;
      }
      const double d = nearestOther(c, k, photo);
      std::printf("    %s %zu only", photo ? "photograph" : "simulation", k + 1);
      if (std::isfinite(d))
        std::printf("  nearest %s hole %.2f mm away", photo ? "simulated" : "photographed", d * 1e3);
      std::printf("\n");
    }
  }
  std::printf("  paired: %zu of %zu photographed hole%s, %zu of %zu simulated\n", paired[0],
              c.photo.size(), c.photo.size() == 1 ? "" : "s", paired[1], c.simulated.size());
}

/// The other side's hole numbers (from 1) that a hole overlaps, joined by `sep`.
std::string partnerList(const HoleComparison& c, std::size_t hole, bool photo_side,
                        const char* sep) {
  std::string s;
  for (std::size_t k : partnersOf(c, hole, photo_side))
    s += (s.empty() ? "" : sep) + std::to_string(k + 1);
  return s;
}

void writeCsv(const std::string& path, const HoleComparison& c) {
  std::ofstream out(path, std::ios::trunc);
  out << "source,hole,area_m2,diameter_m,centroid_u_m,centroid_v_m,overlaps,nearest_other_m\n";
  const auto rows = [&](const char* source, bool photo_side) {
    const std::vector<HoleSize>& holes = photo_side ? c.photo : c.simulated;
    for (std::size_t k = 0; k < holes.size(); ++k) {
      const double d = nearestOther(c, k, photo_side);
      out << source << ',' << k + 1 << ',' << num(holes[k].area) << ',' << num(holes[k].diameter)
          << ',' << num(holes[k].centroid.x()) << ',' << num(holes[k].centroid.y()) << ','
          << partnerList(c, k, photo_side, " ") << ',' << (std::isfinite(d) ? num(d) : "") << '\n';
    }
  };
  rows("photo", true);
  rows("simulation", false);
  if (!out) throw RunError("cannot write " + path);
}

void writeJson(const std::string& path, const CompareOptions& o, const std::string& plate,
               double time, const std::string& image, const PhotoSegmentation& seg,
               const HoleComparison& c, const Eigen::Vector2d& centre_px) {
  std::ofstream out(path, std::ios::trunc);
  const auto holes = [&](bool photo_side) {
    const std::vector<HoleSize>& list = photo_side ? c.photo : c.simulated;
    std::string s = "[";
    for (std::size_t k = 0; k < list.size(); ++k) {
      const double d = nearestOther(c, k, photo_side);
      s += std::string(k ? ", " : "") + "{\"area_m2\": " + num(list[k].area) +
           ", \"diameter_m\": " + num(list[k].diameter) + ", \"centroid_uv_m\": [" +
           num(list[k].centroid.x()) + ", " + num(list[k].centroid.y()) + "], \"overlaps\": [" +
           partnerList(c, k, photo_side, ", ") +
           "], \"nearest_other_m\": " + (std::isfinite(d) ? num(d) : "null") + "}";
    }
    return s + "]";
  };
  std::string pairs = "[";
  for (const HolePair& p : c.pairs)
    pairs += std::string(pairs.size() > 1 ? ", " : "") + "{\"photo\": " +
             std::to_string(p.photo + 1) + ", \"simulation\": " + std::to_string(p.simulated + 1) +
             ", \"overlap_m2\": " + num(p.overlap) + ", \"iou\": " + num(p.iou) + "}";
  pairs += "]";
  std::string quoted = "\"";
  for (char ch : image) quoted += (ch == '"' || ch == '\\') ? std::string("\\") + ch : std::string(1, ch);
  quoted += "\"";
  out << "{\n  \"plate\": \"" << plate << "\",\n  \"time_s\": " << num(time)
      << ",\n  \"image\": " << quoted << ",\n  \"width_px\": " << seg.width
      << ", \"height_px\": " << seg.height << ",\n  \"m_per_px\": " << num(o.m_per_px)
      << ",\n  \"face\": \"" << (o.rear ? "rear" : "front") << "\",\n  \"threshold\": "
      << num(seg.threshold) << ", \"threshold_automatic\": " << (seg.automatic ? "true" : "false")
      << ",\n  \"registration\": \"" << (o.centre_px ? "centre given" : "largest holes' centroids aligned")
      << "\", \"plate_centre_px\": [" << num(centre_px.x()) << ", " << num(centre_px.y()) << "],\n  \"iou\": " << num(c.iou)
      << ", \"photo_px\": " << c.photo_px << ", \"simulation_px\": " << c.simulated_px
      << ", \"both_px\": " << c.both_px << ", \"simulation_outside_fraction\": " << num(c.simulated_outside) << ",\n  \"photo_holes\": " << holes(true)
      << ",\n  \"simulation_holes\": " << holes(false) << ",\n  \"pairs\": " << pairs << "\n}\n";
  if (!out) throw RunError("cannot write " + path);
}

}  // namespace

void addCompareOptions(CLI::App& cmd, CompareCommandOptions& o) {
  cmd.add_option("--plate", o.plate,
                 "Plate: number (1 = first body that is not a projectile) or name");
  cmd.add_option("--image", o.image, "Photograph (PNG, JPEG, TIFF, BMP, PNM)")
      ->required()->check(CLI::ExistingFile);
  cmd.add_option("--mm-per-px", o.mm_per_px, "Photograph scale, mm per pixel")
      ->required()->check(positiveNumber());
  cmd.add_option("--center", o.center,
                 "X,Y: pixel (column, row from the top left) of the plate's centre "
                 "(default: align the largest holes' centroids)");
  cmd.add_option("--threshold", o.threshold,
                 "Brightness in (0, 1) between holes and plate (default: Otsu's)")
      ->check(openFraction());
  cmd.add_option("--holes", o.holes, "Holes are dark (default) or bright")
      ->check(CLI::IsMember({"dark", "bright"}));
  cmd.add_option("--face", o.face, "Face photographed: front (default) or rear")
      ->check(CLI::IsMember({"front", "rear"}));
  cmd.add_option("--time", o.time, "Output time of the run in s (default: the last)")
      ->check(nonNegativeNumber());
  cmd.add_option("--out", o.out, "Output folder (default RUN_DIR/compare)");
}

int compareCommand(const CompareCommandOptions& opt) {
  CompareOptions co;
  co.m_per_px = opt.mm_per_px * 1e-3;
  co.rear = opt.face == "rear";
  if (!opt.center.empty()) {
    double x = 0, y = 0;
    char tail = 0;
    if (std::sscanf(opt.center.c_str(), "%lf,%lf%c", &x, &y, &tail) != 2) {
      std::fprintf(stderr, "error: --center must be X,Y in pixels (column, row from the top left), got '%s'\n",
                   opt.center.c_str());
      return 2;
    }
    co.centre_px = Eigen::Vector2d(x, y);
  }
  SegmentOptions so;
  so.threshold = opt.threshold;
  so.dark_holes = opt.holes == "dark";
  if (!fs::exists(fs::path(opt.run_dir) / "elements.pvd")) {
    std::fprintf(stderr, "error: %s is not a run folder (no elements.pvd)\n", opt.run_dir.c_str());
    return 2;
  }
  try {
    const RunInfo info = readRunInfo(opt.run_dir);
    const int body = plateBody(info, opt.plate);
    const std::string& name = info.bodies[body].name;
    const GrayImage photo = readPhoto(opt.image);
    double time = 0;
    const SimulatedPlate plate =
        readSimulatedPlate(opt.run_dir, opt.time, body, name, info.half, &time);
    const PhotoSegmentation seg = segmentHoles(photo, so);
    // What is compared first, so that a comparison that cannot be made says of what.
    std::printf("fesph compare: plate '%s' at t = %.3f us against %s (%d x %d px, %.4g mm/px, %s face)\n",
                name.c_str(), time * 1e6, opt.image.c_str(), photo.width, photo.height,
                opt.mm_per_px, co.rear ? "rear" : "front");
    std::printf("%s", nearestOutputNote(opt.time, time, "compared").c_str());
    std::printf("  threshold %.4f (%s), holes %s\n", seg.threshold,
                seg.automatic ? "Otsu" : "given", so.dark_holes ? "dark" : "bright");
    std::fflush(stdout);  // before an error on stderr
    const HoleComparison cmp = compareHoles(seg, plate, co);
    const Eigen::Vector2d c0 = cmp.frame.toPixel(Eigen::Vector2d::Zero());
    std::printf("  registration: plate centre at pixel (%.1f, %.1f) (%s)\n", c0.x(), c0.y(),
                co.centre_px ? "given" : "largest holes' centroids aligned");
    printHoles("photograph", cmp.photo);
    printHoles("simulation", cmp.simulated);
    std::printf("  IoU %.4f (overlap %zu px, photograph %zu px, simulation %zu px)\n", cmp.iou,
                cmp.both_px, cmp.photo_px, cmp.simulated_px);
    if (cmp.simulated_outside > 0.01)  // more than pixel rounding
      std::printf("  note: %.0f %% of the simulated holes' area lies outside the photograph and is "
                  "not compared\n",
                  100 * cmp.simulated_outside);
    printPairs(cmp);

    const std::string out = opt.out.empty() ? opt.run_dir + "/compare" : opt.out;
    fs::create_directories(out);
    const std::string stem = out + "/" + name + "_compare";
    writeSideBySide(photo, seg, cmp, plate, stem + "_side.png");
    writeOverlay(photo, seg, cmp, stem + "_overlay.png");
    writeCsv(stem + ".csv", cmp);
    writeJson(stem + ".json", co, name, time, opt.image, seg, cmp, c0);
    std::printf("  side by side: %s_side.png (photograph, holes red | simulation, holes blue)\n"
                "  overlay:      %s_overlay.png (green both, red photograph only, blue simulation only)\n"
                "  data:         %s.csv, %s.json\n",
                stem.c_str(), stem.c_str(), stem.c_str(), stem.c_str());
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const RunError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace fesph
