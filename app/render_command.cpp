// SPDX-License-Identifier: MIT
// `fesph render`: report images of an existing run folder, drawn off-screen (OSMesa).
#include "app/commands.hpp"

#include "core/analysis/hole_metrics.hpp"
#include "core/common/error.hpp"
#include "core/common/number_text.hpp"
#include "render/debris_table.hpp"
#include "render/plate_images.hpp"
#include "render/section_view.hpp"
#include "render/velocity_plot.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>
#include <filesystem>

namespace fesph {

namespace fs = std::filesystem;

namespace {

// WxH, two whole numbers and nothing else.
bool parseSize(const std::string& size, int& width, int& height) {
  const char* end = size.data() + size.size();
  const std::from_chars_result w = std::from_chars(size.data(), end, width);
  if (w.ec != std::errc() || w.ptr == end || *w.ptr != 'x') return false;
  const std::from_chars_result h = std::from_chars(w.ptr + 1, end, height);
  return h.ec == std::errc() && h.ptr == end;
}

}  // namespace

std::string nearestOutputNote(double asked, double found, const std::string& done) {
  // A time between outputs or past the run's end (one typed in us, not s) takes the nearest
  // output: say which.
  if (asked < 0 || std::abs(found - asked) <= 1e-9 * asked) return "";
  return "  no output at t = " + shortestText(asked) + " s: " + done + " at the nearest, t = " +
         shortestText(found) + " s\n";
}

void renderRun(const std::string& run_dir, double time, const std::string& field, int width,
               int height, const std::string& out_dir) {
  ImageOptions o;
  o.width = width;
  o.height = height;
  o.field = field;
  fs::create_directories(out_dir);
  const std::vector<PlateImages> plates = renderPlateImages(run_dir, time, o, out_dir);
  // the output step drawn (with no plate drawn, the step the rest is drawn of)
  const double drawn =
      plates.empty() ? render_detail::readRunStep(run_dir, time).time : plates.front().time;
  std::printf("%s", nearestOutputNote(time, drawn, "drawn").c_str());
  if (plates.empty())  // the section, velocity plot and debris table are drawn all the same
    std::printf("  plates: none drawn, as no body but a projectile has elements or particles "
                "there\n");
  std::vector<PlateHoles> holes;
  for (const PlateImages& p : plates) {
    holes.push_back(p.holes);
    std::printf("  %s: %s, %s (%zu through-hole%s)\n", p.plate.c_str(), p.front_png.c_str(),
                p.rear_png.c_str(), p.holes.holes.size(), p.holes.holes.size() == 1 ? "" : "s");
  }
  std::printf("  section: %s\n", renderSectionView(run_dir, time, o, out_dir + "/section.png").c_str());
  std::printf("  velocity: %s\n",
              renderVelocityPlot({{fs::path(run_dir).filename().string(), run_dir + "/history.csv"}},
                                 "", out_dir + "/velocity.png", o)
                  .c_str());
  writeHolesCsv(out_dir + "/holes.csv", holes);
  writeHolesJson(out_dir + "/holes.json", holes, field, drawn);
  const DebrisSummary debris = writeDebrisTable(run_dir, drawn, plates, out_dir);
  std::printf("  debris: %s/debris.csv (%zu clump%s of free particles, %zu would strike a "
              "plate)\n",
              out_dir.c_str(), debris.clumps, debris.clumps == 1 ? "" : "s", debris.strikes);
}

bool isRenderedFile(const std::string& name) {
  const auto ends = [&](const std::string& tail) {
    return name.size() > tail.size() &&
           name.compare(name.size() - tail.size(), tail.size(), tail) == 0;
  };
  return ends("_front.png") || ends("_rear.png") || name == "section.png" ||
         name == "velocity.png" || name == "holes.csv" || name == "holes.json" ||
         name == "debris.csv";
}

int renderCommand(const RenderOptions& opt) {
  int width = 0, height = 0;
  if (!parseSize(opt.size, width, height) || width < 64 || height < 64 || width > 8192 ||
      height > 8192) {
    std::fprintf(stderr, "error: --size must be WxH with 64..8192 pixels each, got '%s'\n",
                 opt.size.c_str());
    return 2;
  }
  if (!fs::exists(fs::path(opt.run_dir) / "elements.pvd")) {
    std::fprintf(stderr, "error: %s is not a run folder (no elements.pvd)\n", opt.run_dir.c_str());
    return 2;
  }
  const std::string out = opt.out.empty() ? opt.run_dir + "/images" : opt.out;
  try {
    if (opt.times.empty()) {
      renderRun(opt.run_dir, -1.0, opt.field, width, height, out);
    } else {
      for (double t : opt.times)
        renderRun(opt.run_dir, t, opt.field, width, height, out + "/t_" + shortestText(t));
    }
  } catch (const UnknownField& e) {
    std::fprintf(stderr, "error: --field: %s\n", e.what());
    return 2;
  } catch (const RunError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}

}  // namespace fesph
