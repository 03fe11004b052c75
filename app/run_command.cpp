// SPDX-License-Identifier: MIT
// `fesph run`: read the scene, mesh it, run the time loop with output at the scene's cadence,
// and print a summary with figures of merit. Output files stay valid if the run fails.
#include "app/commands.hpp"
#include "app/progress.hpp"

#include "core/analysis/fragments.hpp"
#include "core/common/error.hpp"
#include "core/io/history_csv.hpp"
#include "core/scene/scene.hpp"
#include "core/solver/step.hpp"
#include "core/state/model_build.hpp"
#include "render/series_writer.hpp"

#include <omp.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

namespace fesph {

namespace fs = std::filesystem;

namespace {

// Elements still live: every erosion and conversion is counted, no need to scan.
std::size_t liveElements(const Model& model) {
  return model.elems.size() -
         static_cast<std::size_t>(model.conversion.eroded + model.conversion.converted);
}

void printSummary(const Model& model, double wall_solver, double wall_total,
                  double element_steps, const std::string& folder) {
  const EnergyBudget& en = model.energy;
  std::printf("\nSummary\n");
  std::printf("  elements         %zu (live %zu)\n", model.elems.size(), liveElements(model));
  std::printf("  nodes            %zu\n", model.nodes.size());
  std::printf("  steps            %ld to t = %.6g s\n", model.step, model.time);
  std::printf("  wall time        %.2f s (solver %.2f s)\n", wall_total, wall_solver);
  if (element_steps > 0)
    std::printf("  cost             %.1f ns per element-step (%d threads)\n",
                1e9 * wall_solver / element_steps, omp_get_max_threads());
  std::printf("  energy (J)       kinetic %.6g  internal %.6g  contact %.6g  eroded %.6g\n",
              en.kinetic, en.internal, en.contact, en.eroded);
  const ConversionStats& cs = model.conversion;
  if (cs.eroded + cs.converted > 0)
    std::printf("  conversion       %ld eroded (%.4g kg), %ld converted; triggers: %ld damage, "
                "%ld safety, the rest plastic strain\n",
                cs.eroded, cs.eroded_mass, cs.converted, cs.by_damage, cs.by_safety);
  std::printf("  energy balance   error %.3g %% of the initial %.6g J\n",
              100 * en.balanceError(), en.initial);
  for (std::size_t b = 0; b < model.bodies.size(); ++b) {
    const Body& body = model.bodies[b];
    if (!body.is_projectile) continue;
    const Vec3 v = bodyMeanVelocity(model, static_cast<int>(b));
    std::printf("  projectile '%s'  mean velocity (%.2f, %.2f, %.2f) m/s\n", body.name.c_str(),
                v.x(), v.y(), v.z());
    if (body.elem_end == body.elem_begin || model.bodies.size() < 2) continue;  // no target
    const ResidualVelocity r = residualVelocity(model, static_cast<int>(b));
    std::printf("  residual velocity %.1f m/s (largest intact piece, %.1f %% of the initial "
                "mass; %s)\n",
                r.speed, 100 * r.mass_fraction,
                r.cleared ? "it has cleared every target" : "not clear of the targets yet");
  }
  std::printf("  output           %s\n", folder.c_str());
}

}  // namespace

int runCommand(const RunOptions& opt) {
  const auto t0 = std::chrono::steady_clock::now();
  Scene scene;
  Model model;
  std::vector<std::string> overrides = opt.overrides;
  if (opt.end_time > 0) {
    char value[32];  // std::to_string would print 1e-7 as 0.000000
    std::snprintf(value, sizeof value, "%.17g", opt.end_time);
    overrides.push_back(std::string("simulation.end_time=") + value);
  }
  if (opt.threads > 0) omp_set_num_threads(opt.threads);
  try {
    scene = loadScene(opt.scene, overrides, opt.materials);
    if (!opt.out.empty()) scene.output.folder = opt.out;
    std::printf("fesph %s: scene %s (%s)\n", FESPH_VERSION, opt.scene.c_str(), scene.title.c_str());
    std::printf("Meshing %zu bodies\n", scene.bodies.size());
    model = buildModel(scene, &std::cout);
  } catch (const InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }

  const std::string folder = scene.output.folder;
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) {
    std::fprintf(stderr, "error: cannot create output folder %s: %s\n", folder.c_str(),
                 ec.message().c_str());
    return 2;
  }
  {
    std::ofstream(folder + "/scene.toml") << scene.text;
  }
  std::unique_ptr<SeriesWriter> series;
  try {
    SeriesOptions options;
    options.fields = scene.output.fields;
    series = std::make_unique<SeriesWriter>(folder, options);
  } catch (const std::invalid_argument& e) {
    std::fprintf(stderr, "%s: error: [output] fields: %s\n", opt.scene.c_str(), e.what());
    return 2;
  }
  HistoryCsv history(folder + "/history.csv", model);

  std::printf("Running to t = %.6g s, output every %.6g s, %d threads\n",
              model.controls.end_time, scene.output.interval, omp_get_max_threads());
  Progress progress(model.controls.end_time, !opt.quiet);
  const double end = model.controls.end_time;
  const double interval = scene.output.interval;
  long output_index = 0;
  double wall_solver = 0, element_steps = 0;
  int code = 0;
  try {
    series->write(model, model.time);
    double next_output = interval;
    while (model.time < end * (1 - 1e-12)) {
      const double t_stop = std::min(next_output, end);
      const auto s0 = std::chrono::steady_clock::now();
      step(model, t_stop);
      wall_solver += std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
      element_steps += static_cast<double>(liveElements(model));
      if (model.step % scene.output.history_every == 1) history.record(model);
      if (model.time >= t_stop * (1 - 1e-12)) {
        if (t_stop == next_output || model.time >= end * (1 - 1e-12)) {
          series->write(model, model.time);
          ++output_index;
        }
        next_output = interval * static_cast<double>(output_index + 1);
      }
      progress.update(model.time, model.step, model.dt);
    }
    history.record(model);
  } catch (const RunError& e) {
    progress.finish();
    history.record(model);
    std::fprintf(stderr,
                 "error: run stopped at t = %.6g s, step %ld: %s\n"
                 "Output written so far is valid and kept in %s\n",
                 model.time, model.step, e.what(), folder.c_str());
    code = 1;
  }
  progress.finish();
  const double wall_total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  printSummary(model, wall_solver, wall_total, element_steps, folder);
  if (!opt.no_images) {
    // A failed image must not fail a finished run: warn and keep the exit code.
    std::printf("Images\n");
    try {
      renderRun(folder, -1.0, "damage", 1600, 1200, folder + "/images");
    } catch (const RunError& e) {
      std::fprintf(stderr, "warning: images not drawn: %s\n", e.what());
    }
  }
  return code;
}

}  // namespace fesph
