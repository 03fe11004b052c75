// SPDX-License-Identifier: MIT
#include "app/run_session.hpp"

#include "core/analysis/fragments.hpp"
#include "core/analysis/plate_crossings.hpp"
#include "core/common/error.hpp"
#include "core/solver/figures_of_merit.hpp"
#include "core/solver/step.hpp"
#include "core/state/model_build.hpp"
#include "render/series_writer.hpp"

#include <omp.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <ostream>

namespace fesph {

namespace fs = std::filesystem;

namespace {

// Elements still live: every erosion and conversion is counted, no need to scan.
std::size_t liveElements(const Model& model) {
  return model.elems.size() -
         static_cast<std::size_t>(model.conversion.eroded + model.conversion.converted);
}

// The end time is taken as reached within a relative 1e-12 (sums of steps round).
bool reached(double time, double target) { return time >= target * (1 - 1e-12); }

}  // namespace

RunSession::RunSession() = default;
RunSession::~RunSession() = default;

void RunSession::open(const std::string& scene_path, const std::vector<std::string>& overrides,
                      const std::string& out_folder, const std::string& material_library,
                      std::ostream* log) {
  opened_ = std::chrono::steady_clock::now();
  scene_ = loadScene(scene_path, overrides, material_library);
  if (!out_folder.empty()) scene_.output.folder = out_folder;
  if (log) {
    *log << "fesph " << FESPH_VERSION << ": scene " << scene_path << " (" << scene_.title
         << ")\nMeshing " << scene_.bodies.size() << " bodies" << std::endl;
  }
  model_ = buildModel(scene_, log);

  const std::string& dir = folder();
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw RunError("cannot create output folder " + dir + ": " + ec.message());
  {
    std::ofstream(dir + "/scene.toml") << scene_.text;
  }
  try {
    SeriesOptions options;
    options.fields = scene_.output.fields;
    series_ = std::make_unique<SeriesWriter>(dir, options);
  } catch (const std::invalid_argument& e) {
    throw InputError(scene_path, 0, 0, std::string("[output] fields: ") + e.what());
  }
  history_ = std::make_unique<HistoryCsv>(dir + "/history.csv", model_);
  crossings_ = std::make_unique<PlateCrossings>(scene_, model_);
  next_output_ = scene_.output.interval;
}

bool RunSession::complete() const { return reached(model_.time, endTime()); }

void RunSession::writeOutput() {
  series_->write(model_, model_.time);
  crossings_->writeCsv(folder() + "/residual_velocities.csv");
}

StopReason RunSession::advance(double until_time, long max_steps,
                               const std::atomic<bool>* stop) {
  if (!failure_.empty()) return StopReason::Failed;
  const double end = endTime();
  const double interval = scene_.output.interval;
  try {
    if (!started_) {
      writeOutput();
      started_ = true;
    }
    for (long done = 0;; ++done) {
      if (complete()) return StopReason::EndTime;
      if (stop && stop->load()) return StopReason::Interrupted;
      if ((max_steps >= 0 && done >= max_steps) || model_.time >= until_time)
        return StopReason::Limit;

      const double t_stop = std::min(next_output_, end);
      const auto s0 = std::chrono::steady_clock::now();
      step(model_, t_stop);
      wall_solver_ +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
      element_steps_ += static_cast<double>(liveElements(model_));
      crossings_->update(model_);
      if (model_.step % scene_.output.history_every == 1) history_->record(model_);
      if (reached(model_.time, t_stop)) {
        if (t_stop == next_output_ || complete()) {
          writeOutput();
          ++output_index_;
        }
        next_output_ = interval * static_cast<double>(output_index_ + 1);
      }
      if (complete()) history_->record(model_);
      if (on_step_) on_step_(model_);
    }
  } catch (const RunError& e) {
    failure_ = e.what();
    history_->record(model_);
    crossings_->writeCsv(folder() + "/residual_velocities.csv");
    return StopReason::Failed;
  }
}

void RunSession::printSummary() const {
  const Model& model = model_;
  const double wall_total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - opened_).count();
  const EnergyBudget& en = model.energy;
  std::printf("\nSummary\n");
  std::printf("  elements         %zu (live %zu)\n", model.elems.size(), liveElements(model));
  std::printf("  nodes            %zu\n", model.nodes.size());
  std::printf("  steps            %ld to t = %.6g s\n", model.step, model.time);
  std::printf("  wall time        %.2f s (solver %.2f s)\n", wall_total, wall_solver_);
  if (element_steps_ > 0)
    std::printf("  cost             %.1f ns per element-step (%d threads)\n",
                1e9 * wall_solver_ / element_steps_, omp_get_max_threads());
  printFiguresOfMerit(model);  // cost by phase, memory
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
  const auto& plates = crossings_->plates();
  for (std::size_t k = 0; k < plates.size(); ++k) {
    const PlateCrossing& p = plates[k];
    if (p.t_measured >= 0)
      std::printf("  after plate %zu    %.1f m/s at t = %.4g s ('%s'; piece %.1f %% of the mass)\n",
                  k + 1, p.speed, p.t_measured, p.name.c_str(), 100 * p.mass_fraction);
    else
      std::printf("  after plate %zu    not measured (%s)\n", k + 1,
                  p.t_contact >= 0 ? "hit, not through yet" : "not reached");
  }
  std::printf("  output           %s\n", folder().c_str());
}

}  // namespace fesph
