// SPDX-License-Identifier: MIT
#include "app/run_session.hpp"

#include "app/commands.hpp"

#include "core/analysis/fragments.hpp"
#include "core/analysis/plate_crossings.hpp"
#include "core/analysis/symmetry_leak.hpp"
#include "core/common/error.hpp"
#include "core/io/replace_file.hpp"
#include "core/solver/figures_of_merit.hpp"
#include "core/solver/step.hpp"
#include "core/state/model_build.hpp"
#include "render/series_writer.hpp"

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <sstream>

namespace fesph {

namespace fs = std::filesystem;

namespace {

// Elements still live: every erosion and conversion is counted, no need to scan.
std::size_t liveElements(const Model& model) {
  return model.elems.size() -
         static_cast<std::size_t>(model.conversion.eroded + model.conversion.converted);
}

void makeFolder(const std::string& dir) {
  std::error_code ec;
  fs::create_directories(dir, ec);
  if (ec) throw RunError("cannot create output folder " + dir + ": " + ec.message());
}

// The end time is taken as reached within a relative 1e-12 (sums of steps round).
bool reached(double time, double target) { return time >= target * (1 - 1e-12); }

}  // namespace

RunSession::RunSession() = default;
RunSession::~RunSession() = default;

void RunSession::open(const std::string& scene_path, const std::vector<std::string>& overrides,
                      const std::string& out_folder, const std::string& material_library,
                      std::ostream* log, bool defer_output) {
  opened_ = std::chrono::steady_clock::now();
  scene_ = loadScene(scene_path, overrides, material_library);
  if (!out_folder.empty()) scene_.output.folder = out_folder;
  // The folder before the meshing, which can take minutes: a bad --out is said at once. A
  // folder made here is taken away again if the meshing fails.
  const bool existed = fs::exists(folder());
  makeFolder(folder());
  lock_.take(folder());  // before the meshing too: another run there is said at once
  if (log) {
    *log << "fesph " << FESPH_VERSION << ": scene " << scene_path << " (" << scene_.title
         << ")\nMeshing " << scene_.bodies.size() << " bodies" << std::endl;
  }
  try {
    model_ = buildModel(scene_, log);
  } catch (...) {
    lock_.release();
    if (!existed) {  // the folder made above, with nothing but the lock in it
      std::error_code ec;
      fs::remove(lockFile(folder()), ec);
      fs::remove(folder(), ec);  // only if empty now
    }
    throw;
  }
  crossings_ = allPlateCrossings(scene_, model_);
  for (const PlateCrossings& c : crossings_) {
    if (!log || !c.headsAway()) continue;
    const Vec3 v = bodyMeanVelocity(model_, c.projectile());
    *log << scene_path << ":" << scene_.bodies[c.projectile()].line << ": warning: projectile '"
         << c.projectileName() << "' moves away from every plate, at (" << v.x() << ", "
         << v.y() << ", " << v.z()
         << ") m/s: no plate will be crossed (is the velocity's sign right?)" << std::endl;
  }

  next_output_ = scene_.output.interval;
  next_checkpoint_ = scene_.output.checkpoint_interval;
  log_ = log;
  if (!defer_output) startOutput();
}

// Once: the run the folder holds goes, this one's writers open.
void RunSession::startOutput() {
  if (outputStarted()) return;
  clearEarlierRun(log_);
  openWriters(false, RunProgress{});
}

void RunSession::restart(const std::string& checkpoint, const std::vector<std::string>& overrides,
                         const std::string& out_folder, std::ostream* log) {
  opened_ = std::chrono::steady_clock::now();
  RunProgress saved;
  model_ = readCheckpoint(checkpoint, saved);
  // A checkpoint holds the meshes, materials, symmetry planes and state: a change to any of
  // them would be read and then never used. Refused, not ignored (the run's own overrides,
  // given again, change nothing).
  for (const std::string& o : overrides) {
    if (std::find(saved.overrides.begin(), saved.overrides.end(), o) != saved.overrides.end())
      continue;
    const std::string key = o.substr(0, o.find('='));
    for (const std::string fixed : {"bodies", "materials", "boundary", "resolution",
                                    "resolutions", "simulation.symmetry"}) {
      if (key != fixed && key.rfind(fixed + ".", 0) != 0) continue;
      throw InputError("--set " + o, 0, 0,
                       "a restart goes on with the checkpoint's meshes, materials and state: '" +
                           fixed + "' cannot change (the rest of [simulation], and [output], "
                           "[contact], [conversion], [sph] and [reference] can); run the scene "
                           "again instead");
    }
  }
  std::vector<std::string> all = saved.overrides;
  all.insert(all.end(), overrides.begin(), overrides.end());
  scene_ = loadSceneText(saved.scene_text, saved.scene_path, all, saved.material_library);
  // The solver controls follow the scene: the run's own unless new overrides change them (a
  // later end time, a different dt floor). Materials and the state are the checkpoint's.
  model_.controls = scene_.controls;
  model_.sph.controls = scene_.sph;
  if (!reached(endTime(), model_.time))
    throw InputError(checkpoint, 0, 0,
                     "the end time " + seconds(endTime()) + " lies before the checkpoint's t = " +
                         seconds(model_.time) +
                         ": nothing to run (give a later simulation.end_time; fesph run: "
                         "--end-time)");
  if (model_.symmetry.empty()) model_.symmetry = scene_.symmetry;  // format 4 did not keep them
  const fs::path parent = fs::path(checkpoint).parent_path();
  scene_.output.folder = !out_folder.empty() ? out_folder
                         : parent.empty()    ? std::string(".")
                                             : parent.string();
  if (log) {
    *log << "fesph " << FESPH_VERSION << ": restart of scene " << saved.scene_path << " ("
         << scene_.title << ") from " << checkpoint << " at t = " << model_.time << " s, step "
         << model_.step << std::endl;
  }
  crossings_.clear();
  for (const CrossingsRecord& c : saved.crossings)
    crossings_.emplace_back(c.plates, c.projectile, model_.bodies[c.projectile].name);
  // The series and histories go on in the checkpoint's own run folder; another folder gets
  // fresh ones, starting at the checkpoint.
  std::error_code ec;
  const bool own =
      out_folder.empty() || fs::equivalent(out_folder, parent.empty() ? "." : parent, ec);
  makeFolder(folder());
  lock_.take(folder());
  if (own) {
    refuseToCutLaterCheckpoints(checkpoint);
    refuseAnotherRunsHistory(checkpoint, saved);
  } else {
    clearEarlierRun(log);  // fresh series and histories there: the run there before goes whole
  }
  openWriters(own, saved);
  started_ = true;
  last_output_time_ = series_->lastTime();  // the series cut back to the checkpoint, or fresh
  output_index_ = saved.output_index;
  next_output_ = saved.next_output;
  next_checkpoint_ = saved.next_checkpoint;
}

// A run into a folder replaces the run there whole: the series writer removes its steps, and
// here go its checkpoints (which would go on with this run's records cut back under them, and
// outnumber its own when the oldest are pruned) and the images fesph drew of it (which would
// show that run as this one's). Only files of fesph's own naming: anything else stays.
void RunSession::clearEarlierRun(std::ostream* log) const {
  std::error_code ec;
  // the writers opened next replace these
  const bool series = fs::exists(fs::path(folder()) / "elements.pvd", ec) ||
                      fs::exists(fs::path(folder()) / "history.csv", ec);
  std::size_t checkpoints = 0, images = 0;
  for (const std::string& path : listCheckpoints(folder())) checkpoints += fs::remove(path, ec);
  const auto clear = [&](const fs::path& dir) {  // drawn files, then the folder if empty
    for (const fs::directory_entry& f : fs::directory_iterator(dir, ec))
      if (f.is_regular_file(ec) && isRenderedFile(f.path().filename().string()))
        images += fs::remove(f.path(), ec);
    if (fs::is_empty(dir, ec)) fs::remove(dir, ec);
  };
  const fs::path image_dir = fs::path(folder()) / "images";
  if (fs::is_directory(image_dir, ec)) {
    std::vector<fs::path> times;  // `fesph render --time` folders, t_TIME
    for (const fs::directory_entry& f : fs::directory_iterator(image_dir, ec))
      if (f.is_directory(ec) && f.path().filename().string().rfind("t_", 0) == 0)
        times.push_back(f.path());
    for (const fs::path& t : times) clear(t);
    clear(image_dir);
  }
  if (!log || (!series && checkpoints + images == 0)) return;
  const auto count = [](std::size_t n, const char* one, const char* many) {
    return std::to_string(n) + " " + (n == 1 ? one : many);
  };
  std::vector<std::string> parts;
  if (series) parts.push_back("series and histories");
  if (checkpoints > 0) parts.push_back(count(checkpoints, "checkpoint", "checkpoints"));
  if (images > 0) parts.push_back(count(images, "file", "files") + " of images/");
  std::string removed = parts[0];
  for (std::size_t k = 1; k < parts.size(); ++k)
    removed += (k + 1 == parts.size() ? " and " : ", ") + parts[k];
  *log << folder() << ": the run there before is replaced: its " << removed << std::endl;
}

// Going back in the checkpoint's own folder cuts its series and histories back to the
// checkpoint; a later checkpoint there would lose the records it needs to be restarted.
void RunSession::refuseToCutLaterCheckpoints(const std::string& checkpoint) const {
  const std::string here = fs::path(checkpointPath(folder(), model_.step)).filename().string();
  std::string later;
  for (const std::string& path : listCheckpoints(folder()))
    if (fs::path(path).filename().string() > here) later = fs::path(path).filename().string();
  if (later.empty()) return;
  throw RunError(folder() + " holds a later checkpoint (" + later + ") than " + checkpoint +
                 " (step " + std::to_string(model_.step) +
                 "); going on from it there would cut the run's series and histories back "
                 "and leave the later checkpoint without them. Restart into another folder "
                 "(--out DIR), or delete the later checkpoints to go back in this one");
}

void RunSession::openWriters(bool resume, const RunProgress& saved) {
  const std::string& dir = folder();
  makeFolder(dir);
  try {
    SeriesOptions options;
    options.fields = scene_.output.fields;
    options.append = resume;
    options.keep = static_cast<std::size_t>(saved.series_outputs);
    options.material_names = scene_.material_ids;
    series_ = std::make_unique<SeriesWriter>(dir, options);
  } catch (const std::invalid_argument& e) {
    throw InputError(scene_.path, 0, 0, std::string("[output] fields: ") + e.what());
  }
  // A restart into a new folder starts its histories there.
  const std::string csv = dir + "/history.csv", h5 = dir + "/run.h5";
  const auto rows = static_cast<std::size_t>(saved.history_rows);
  history_ = resume && fs::exists(csv) ? std::make_unique<HistoryCsv>(csv, rows)
                                       : std::make_unique<HistoryCsv>(csv, model_);
  history_h5_ = resume && fs::exists(h5) ? std::make_unique<HistoryH5>(h5, model_, rows)
                                         : std::make_unique<HistoryH5>(h5, model_, scene_.text);
  // The scene last: a restart refused by the writers above leaves the folder's run as it was.
  std::ofstream(dir + "/scene.toml") << scene_.text;
  std::ofstream(dir + "/scene_source.toml") << scene_.source;
}

RunProgress RunSession::progress() const {
  RunProgress p;
  p.scene_text = scene_.source;
  p.overrides = scene_.overrides;
  p.scene_path = fs::absolute(scene_.path).string();
  p.material_library = fs::absolute(scene_.material_library).string();
  p.series_outputs = static_cast<long>(series_->outputCount());
  p.output_index = output_index_;
  p.next_output = next_output_;
  p.next_checkpoint = next_checkpoint_;
  p.history_rows = static_cast<long>(history_h5_->rows());
  p.history_last_row = history_->lastRow();
  for (const PlateCrossings& c : crossings_) p.crossings.push_back({c.projectile(), c.plates()});
  return p;
}

// Another run into the folder since the checkpoint replaced its series and histories (and
// removed its checkpoints, but one may be put back): going on there would cut that run's
// records back to the checkpoint's counts and continue them with this run's state. The
// history's row at the checkpoint tells (a run that is the same to every digit writes the
// same row, and may go on).
void RunSession::refuseAnotherRunsHistory(const std::string& checkpoint,
                                          const RunProgress& saved) const {
  if (saved.history_rows <= 0 || saved.history_last_row.empty()) return;  // older checkpoint
  const std::string csv = folder() + "/history.csv";
  if (HistoryCsv::row(csv, static_cast<std::size_t>(saved.history_rows)) ==
      saved.history_last_row)
    return;
  throw RunError(folder() + " holds another run than the one " + checkpoint +
                 " was taken in (row " + std::to_string(saved.history_rows) + " of " + csv +
                 " is not the one the checkpoint kept); going on there would join the two. "
                 "Restart into another folder (--out DIR)");
}

void RunSession::checkpoint(const std::string& path) {
  startOutput();  // the checkpoint goes with this run's series and histories
  writeCheckpoint(path, model_, progress());
}

std::string RunSession::checkpoint() {
  const std::string path = checkpointPath(folder(), model_.step);
  checkpoint(path);
  pruneCheckpoints(folder(), static_cast<std::size_t>(scene_.output.checkpoints_kept));
  return path;
}

// One row a step: the end time, or a failure, can fall on a step that has its row already
// (taken at the interval, or before the checkpoint a run continues from).
void RunSession::recordHistory() {
  if (history_->endsAt(model_.energy.time)) return;
  history_->record(model_);
  history_h5_->record(model_);
}

bool RunSession::complete() const { return reached(model_.time, endTime()); }

void RunSession::writeOutput() {
  series_->write(model_, model_.time);
  last_output_time_ = model_.time;
  writeCrossingsCsv(folder() + "/residual_velocities.csv", crossings_);
  // A run killed outright (SIGKILL, the machine going down) cannot write its summary at the
  // end: this one, at its last output, says how far it got instead of an earlier segment's.
  writeSummary(folder() + "/summary.toml", "running");
}

StopReason RunSession::advance(double until_time, long max_steps,
                               const std::atomic<bool>* stop) {
  if (!failure_.empty()) return StopReason::Failed;
  const double end = endTime();
  const double interval = scene_.output.interval;
  startOutput();
  try {
    if (!started_) {
      writeOutput();
      started_ = true;
    }
    for (long done = 0;; ++done) {
      if (complete()) return StopReason::EndTime;
      if (stop && stop->load()) {
        // the crossings since the last output are in memory only: keep them with the checkpoint
        writeCrossingsCsv(folder() + "/residual_velocities.csv", crossings_);
        return StopReason::Interrupted;
      }
      if ((max_steps >= 0 && done >= max_steps) || model_.time >= until_time)
        return StopReason::Limit;

      const double t_stop = std::min(next_output_, end);
      const auto s0 = std::chrono::steady_clock::now();
      step(model_, t_stop);
      wall_solver_ +=
          std::chrono::duration<double>(std::chrono::steady_clock::now() - s0).count();
      element_steps_ += static_cast<double>(liveElements(model_));
      for (PlateCrossings& c : crossings_) c.update(model_);
      if (model_.energy.step % scene_.output.history_every == 0) recordHistory();  // 0, n, 2n...
      if (reached(model_.time, t_stop)) {
        if (t_stop == next_output_ || complete()) {
          writeOutput();
          ++output_index_;
        }
        next_output_ = interval * static_cast<double>(output_index_ + 1);
      }
      if (complete()) recordHistory();
      const double every = scene_.output.checkpoint_interval;
      if (every > 0 && (reached(model_.time, next_checkpoint_) || complete())) {
        next_checkpoint_ = every * (std::floor(model_.time / every * (1 + 1e-12)) + 1);
        checkpoint();
      }
      if (on_step_) on_step_(model_);
    }
  } catch (const RunError& e) {
    failure_ = e.what();
    try {
      recordHistory();
    } catch (const RunError& h) {
      failure_ += std::string(" (and the last history row was not written: ") + h.what() + ")";
    }
    try {
      writeCrossingsCsv(folder() + "/residual_velocities.csv", crossings_);
    } catch (const RunError& c) {
      failure_ += std::string(" (and the residual velocities were not rewritten: ") + c.what() +
                  ")";
    }
    writeFailedState();
    return StopReason::Failed;
  }
}

void RunSession::writeFailedState() {
  // The state the run stopped in, as its last output: the error names an element or a
  // particle, and this is where to look at it. Not when it holds non-finite positions or
  // velocities (nothing could draw them), nor twice at one time.
  const auto finite = [](const std::vector<Vec3>& field) {
    return std::all_of(field.begin(), field.end(), [](const Vec3& a) { return a.allFinite(); });
  };
  if (!(model_.time > last_output_time_)) return;
  if (!finite(model_.nodes.x) || !finite(model_.nodes.v) || !finite(model_.particles.x) ||
      !finite(model_.particles.v)) {
    failure_ += " (the state it stopped in holds non-finite values: not written as an output)";
    return;
  }
  try {
    writeOutput();
  } catch (const std::exception& w) {
    failure_ += std::string(" (and the state it stopped in was not written: ") + w.what() + ")";
  }
}

void RunSession::writeSummary(const std::string& path, const std::string& status) const {
  // TOML, so that `fesph report` (and any tool) reads it back without a parser of its own.
  const Model& m = model_;
  const double wall_total =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - opened_).count();
  const char* modes[] = {"none", "erosion", "sph"};
  std::ostringstream out;
  out.precision(10);
  out << "# fesph run summary\n"
      << "status = \"" << status << "\"\n"
      << "time = " << m.time << "\nend_time = " << endTime() << "\nsteps = " << m.step << "\n"
      << "wall_time_s = " << wall_total << "\nsolver_time_s = " << wall_solver_ << "\n"
      << "threads = " << omp_get_max_threads() << "\n"
      << "resolution = \"" << scene_.resolution << "\"\n"
      << "conversion_mode = \"" << modes[static_cast<int>(m.controls.conversion.mode)] << "\"\n"
      << "plastic_strain = " << m.controls.conversion.plastic_strain << "\n"
      << "elements = " << m.elems.size() << "\nlive_elements = " << liveElements(m) << "\n"
      << "particles = " << m.particles.size() << "\n"
      << "converted = " << m.conversion.converted << "\neroded = " << m.conversion.eroded << "\n"
      << "eroded_mass_kg = " << m.conversion.eroded_mass << "\n"
      << "energy_balance = " << m.energy.balanceError() << "\n";
  if (!scene_.symmetry.empty()) {  // a check: none may cross (docs/sph.md, "Symmetry planes")
    long across = 0;
    double mass = 0, fraction = 0;
    for (const SymmetryLeak& leak : particlesAcrossSymmetry(m, scene_.symmetry)) {
      across += leak.particles;
      mass += leak.mass;
      fraction += leak.mass_fraction;
    }
    out << "particles_across_symmetry = " << across << "\n"
        << "particle_mass_across_symmetry_kg = " << mass << "\n"
        << "particle_mass_fraction_across_symmetry = " << fraction << "\n";
  }
  if (element_steps_ > 0) out << "ns_per_element_step = " << 1e9 * wall_solver_ / element_steps_ << "\n";
  replaceFile(path, out.str());  // a reader never sees half a summary
}

const PlateCrossings* RunSession::crossingsOf(int body) const {
  for (const PlateCrossings& c : crossings_)
    if (c.projectile() == body) return &c;
  return nullptr;
}

const char* RunSession::clearance(int body, const ResidualVelocity& r) const {
  if (!r.cleared) return "not clear of the targets yet";
  // Nothing ahead of a projectile that never reached a plate: it went the other way.
  const PlateCrossings* c = crossingsOf(body);
  if (c && c->reachedNone())
    return "no target ahead of it, and it has reached none";
  return "it has cleared every target";
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
  std::printf("  energy (J)       kinetic %.6g  internal %.6g  contact %.6g  eroded %.6g%s%s\n",
              en.kinetic, en.internal, en.contact, en.eroded, model.symmetry.empty() ? "" : "  ",
              model.symmetry.empty() ? "" : kModelledPart);
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
    if (model.bodies.size() < 2) continue;  // no target
    const ResidualVelocity r = residualVelocity(model, static_cast<int>(b));
    std::printf("  residual velocity %.1f m/s (largest intact piece, %.1f %% of the initial "
                "mass; %s)\n",
                r.speed, 100 * r.mass_fraction, clearance(static_cast<int>(b), r));
    const PlateCrossings* crossings = crossingsOf(static_cast<int>(b));
    if (!crossings) continue;
    const auto& plates = crossings->plates();
    for (std::size_t k = 0; k < plates.size(); ++k) {
      const PlateCrossing& p = plates[k];
      if (p.t_measured >= 0) {
        std::printf("  after plate %zu    %.1f m/s at t = %.4g s ('%s'; piece %.1f %% of the "
                    "mass)\n",
                    k + 1, p.speed, p.t_measured, p.name.c_str(), 100 * p.mass_fraction);
        if (std::isfinite(p.through_mass_fraction))
          std::printf("                   all projectile material through it: %.1f m/s, %.1f %% "
                      "of the mass\n",
                      p.through_velocity.norm(), 100 * p.through_mass_fraction);
      } else
        std::printf("  after plate %zu    not measured (%s)\n", k + 1,
                    p.t_contact >= 0 ? "hit, not through yet" : "not reached");
    }
  }
  for (const SymmetryLeak& leak : particlesAcrossSymmetry(model, scene_.symmetry))
    if (leak.particles > 0)
      std::printf("  symmetry plane   %ld particles (%.4g kg, %.1f %% of the particles' mass) are "
                  "across %c = %g m, which the mirror images should prevent: the half model's "
                  "results are not to be trusted (docs/sph.md, \"Symmetry planes\")\n",
                  leak.particles, leak.mass, 100 * leak.mass_fraction,
                  static_cast<char>('x' + leak.plane->axis), leak.plane->position);
  std::printf("  output           %s\n", folder().c_str());
}

}  // namespace fesph
