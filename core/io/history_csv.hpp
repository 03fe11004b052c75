// SPDX-License-Identifier: MIT
// CSV time history of a run: energy budget by term, momentum, mean velocity of every body.
// Each row is flushed, so a run that stops keeps a valid file up to its last step.
#pragma once

#include "core/state/model.hpp"

#include <fstream>
#include <string>

namespace fesph {

class HistoryCsv {
 public:
  /// Create (or truncate) `path` and write the header for the model's bodies.
  HistoryCsv(const std::string& path, const Model& model);
  /// Continue the file of a restarted run: keep its header and first `rows` rows, drop the
  /// rest (written after the checkpoint), and append from there. Throws RunError.
  HistoryCsv(const std::string& path, std::size_t rows);
  /// Append the budget at model.energy.time.
  void record(const Model& model);
  const std::string& path() const { return path_; }
  /// Whether the last row (a continued file's included) is the budget at `time`: a step's
  /// row is written once. By its time, not its step: files of fesph before checkpoint format
  /// 13 label a row with the step after its time's.
  bool endsAt(double time) const;
  /// The last row's text, without its line break ("" before the first). A checkpoint keeps
  /// it, so that a restart can tell its own run's history from another run's in the folder.
  const std::string& lastRow() const { return last_row_; }
  /// Row `n` (1: the first after the header) of the history file at `path`, without its line
  /// break; "" when the file cannot be read or has fewer rows.
  static std::string row(const std::string& path, std::size_t n);

 private:
  static std::string timeText(double time);  ///< a row's time column

  std::string path_;
  std::ofstream out_;
  std::string last_row_;
};

}  // namespace fesph
