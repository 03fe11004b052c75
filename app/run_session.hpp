// SPDX-License-Identifier: MIT
// One run of a scene, driven in pieces: open (read, mesh, create the writers), advance to a
// time or by a number of steps (output at the scene's cadence, history rows), summary.
// `fesph run` drives it to the end time; an interactive shell can drive it step by step.
#pragma once

#include "app/folder_lock.hpp"
#include "core/io/checkpoint.hpp"
#include "core/io/history_csv.hpp"
#include "core/io/history_h5.hpp"
#include "core/scene/scene.hpp"
#include "core/state/model.hpp"

#include <atomic>
#include <chrono>
#include <functional>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

namespace fesph {

class SeriesWriter;
struct ResidualVelocity;

/// Said of a model with symmetry planes beside its energies, momentum and masses (its
/// velocities are the full bodies').
inline constexpr const char* kModelledPart =
    "(the modelled part's, without its mirror images)";

/// Why RunSession::advance returned.
enum class StopReason {
  EndTime,      ///< the scene's end time is reached: the run is complete
  Limit,        ///< the requested time or step count is reached
  Interrupted,  ///< the stop flag was set (checked after every step)
  Failed,       ///< the solver threw a RunError: see RunSession::failure()
};

class RunSession {
 public:
  RunSession();
  ~RunSession();
  RunSession(const RunSession&) = delete;
  RunSession& operator=(const RunSession&) = delete;

  /// Read the scene (with `--set` style overrides), mesh it, create the output folder (empty
  /// `out_folder`: the scene's [output].folder) and start the output there: the run the
  /// folder holds is replaced (its series, checkpoints and images removed), scene.toml
  /// written and the series and history writers opened. With `defer_output` the folder's
  /// earlier run stays until the first advance or checkpoint starts the output.
  /// Meshing figures, and what the start of the output replaces, go to `log` when given.
  /// Throws InputError (bad scene) or RunError (output folder or files not writable).
  void open(const std::string& scene_path, const std::vector<std::string>& overrides,
            const std::string& out_folder, const std::string& material_library = "",
            std::ostream* log = nullptr, bool defer_output = false);
  /// The output is started: the folder holds this run, not an earlier one.
  bool outputStarted() const { return series_ != nullptr; }

  /// Continue the run saved in `checkpoint`: the scene is the one stored in it (with further
  /// `overrides`, e.g. a later end time), the state is the checkpoint's, and the series,
  /// history.csv and run.h5 of the run folder (empty `out_folder`: the checkpoint's folder)
  /// are cut back to where they stood at the checkpoint and continued.
  /// Throws RunError (unreadable checkpoint, outputs missing) or InputError (overrides).
  void restart(const std::string& checkpoint, const std::vector<std::string>& overrides,
               const std::string& out_folder, std::ostream* log = nullptr);

  /// Write a checkpoint of the state after the last step to `path`. Throws RunError.
  void checkpoint(const std::string& path);
  /// Write FOLDER/checkpoint_<step>.h5, keep the scene's [output].checkpoints_kept newest,
  /// and return its path. Throws RunError.
  std::string checkpoint();

  /// Step until the model time reaches `until_time` (the step that crosses it is not cut
  /// short, so how a run is split into advances never changes its results), `max_steps`
  /// steps are done (< 0: no limit), the end time is reached or `*stop` becomes true.
  /// The first call writes the initial output. Fields are written at the scene's interval,
  /// history rows every [output].history_every steps and once at the end time.
  /// Checkpoints are written at [output].checkpoint_interval and at the end time.
  /// A RunError stops the run: the history gets its last row and Failed is returned.
  StopReason advance(double until_time, long max_steps = -1,
                     const std::atomic<bool>* stop = nullptr);

  /// Called after every step (progress display, live views).
  void onStep(std::function<void(const Model&)> callback) { on_step_ = std::move(callback); }

  /// The end time is reached (advance has nothing left to do).
  bool complete() const;
  /// The RunError message of a failed advance; empty otherwise.
  const std::string& failure() const { return failure_; }

  /// Write summary.toml: `status` ("complete", "failed", "interrupted"; "running" at every
  /// field output until the run ends; the shell's "paused"), times, counts, conversion
  /// settings, energy balance, cost. Read by `fesph report`. Throws RunError.
  void writeSummary(const std::string& path, const std::string& status) const;

  /// Print the run summary (counts, wall time, energy budget, projectile figures) to stdout.
  void printSummary() const;

  const Model& model() const { return model_; }
  Model& model() { return model_; }
  const Scene& scene() const { return scene_; }
  /// The residual-velocity tracking of projectile `body` (plate_crossings.hpp), as measured so
  /// far; null for a body that is none.
  const PlateCrossings* crossingsOf(int body) const;
  /// How the largest piece `r` of projectile `body` stands to the targets, in words: not clear
  /// of them yet, clear of every one, or clear of them without having reached any (shot away
  /// from the plates).
  const char* clearance(int body, const ResidualVelocity& r) const;
  const std::string& folder() const { return scene_.output.folder; }
  double endTime() const { return model_.controls.end_time; }

 private:
  void writeOutput();
  void recordHistory();
  void refuseToCutLaterCheckpoints(const std::string& checkpoint) const;
  void refuseAnotherRunsHistory(const std::string& checkpoint, const RunProgress& saved) const;
  void clearEarlierRun(std::ostream* log) const;
  void startOutput();
  void writeFailedState();
  void openWriters(bool resume, const RunProgress& progress);
  RunProgress progress() const;

  FolderLock lock_;  ///< the run folder's: first here, so let go after the writers close
  Scene scene_;
  Model model_;
  std::unique_ptr<SeriesWriter> series_;
  std::unique_ptr<HistoryCsv> history_;
  std::vector<PlateCrossings> crossings_;
  std::unique_ptr<HistoryH5> history_h5_;
  std::function<void(const Model&)> on_step_;
  std::ostream* log_ = nullptr;  ///< open's log, for the output started later
  std::string failure_;
  bool started_ = false;     ///< the initial output is written
  long output_index_ = 0;    ///< field outputs written after the initial one
  double last_output_time_ = -1;  ///< time of the last field output written, s
  double next_output_ = 0;   ///< time of the next field output, s
  double next_checkpoint_ = 0;  ///< time of the next checkpoint, s
  double wall_solver_ = 0;   ///< s spent in step()
  double element_steps_ = 0; ///< live elements summed over the steps
  std::chrono::steady_clock::time_point opened_;
};

}  // namespace fesph
