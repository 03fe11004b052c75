// SPDX-License-Identifier: MIT
// Checkpoints: the full solver state (every array and number step() reads) in one HDF5 file,
// plus where the run's outputs stood, so that a restarted run continues bit for bit.
// Written under a temporary name and renamed, so a checkpoint on disk is always complete.
#pragma once

#include "core/analysis/plate_crossings.hpp"
#include "core/state/model.hpp"

#include <cstddef>
#include <string>
#include <vector>

namespace fesph {

/// One projectile's residual-velocity tracking (plate_crossings.hpp), as a checkpoint keeps it.
struct CrossingsRecord {
  int projectile = -1;                ///< its body
  std::vector<PlateCrossing> plates;  ///< in the order it meets them
};

/// What a run needs besides the Model to continue its outputs.
struct RunProgress {
  std::string scene_text;        ///< the scene file's text
  std::vector<std::string> overrides;  ///< the --set overrides it was run with
  std::string scene_path;        ///< the scene file, absolute
  std::string material_library;  ///< the material library it was read with, absolute
  long series_outputs = 0;       ///< files in the field series
  long output_index = 0;         ///< field outputs after the initial one
  double next_output = 0;        ///< s
  double next_checkpoint = 0;    ///< s
  long history_rows = 0;         ///< rows in history.csv and run.h5
  /// history.csv's last row at the checkpoint ("" when not known: format 11 and older)
  std::string history_last_row;
  std::vector<CrossingsRecord> crossings;  ///< one per projectile, in the order of the bodies
};

/// Write `model` and `run` to `path` (through `path`.tmp and a rename). Throws RunError.
void writeCheckpoint(const std::string& path, const Model& model, const RunProgress& run);

/// Read a checkpoint. A missing, truncated, damaged or foreign file, or one whose arrays do
/// not fit together, throws RunError naming the file and what is wrong.
Model readCheckpoint(const std::string& path, RunProgress& run);

/// Checkpoint file name of a step in a run folder: FOLDER/checkpoint_SSSSSSSSS.h5.
std::string checkpointPath(const std::string& folder, long step);

/// Delete the oldest checkpoints of `folder` (by step) so that `keep` remain.
void pruneCheckpoints(const std::string& folder, std::size_t keep);

/// Checkpoints in `folder`, oldest first.
std::vector<std::string> listCheckpoints(const std::string& folder);

}  // namespace fesph
