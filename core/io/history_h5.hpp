// SPDX-License-Identifier: MIT
// The run's HDF5 file (run.h5): metadata (scene text, fesph version, git commit, units) and
// the time histories as extendible chunked datasets under /history, one row per record:
// energy by term, momentum, body and projectile velocities, element and particle counts,
// time step and what limited it. Flushed after every row, so that it stays readable if the
// run stops. Read it with h5dump, h5py or any HDF5 tool.
#pragma once

#include "core/io/hdf5.hpp"
#include "core/state/model.hpp"

#include <memory>
#include <string>
#include <vector>

namespace fesph {

class HistoryH5 {
 public:
  /// Create (or replace) `path` with the metadata and empty tables for the model's bodies.
  HistoryH5(const std::string& path, const Model& model, const std::string& scene_text);
  /// Continue the file of a restarted run, cut to its first `rows` rows. Throws RunError if
  /// it is not a run file of this model.
  HistoryH5(const std::string& path, const Model& model, std::size_t rows);
  /// Append the state after the last step.
  void record(const Model& model);
  std::size_t rows() const { return rows_; }

 private:
  void openTables(const Model& model, bool create, std::size_t rows);

  h5::Handle file_;
  std::vector<h5::Table> tables_;
  std::size_t rows_ = 0;
  int projectile_ = -1;  ///< body reported as the projectile, -1: none
};

}  // namespace fesph
