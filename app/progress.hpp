// SPDX-License-Identifier: MIT
// Progress display of a run: a bar with simulated time, steps and ETA on a terminal, plain
// lines every few percent otherwise (logs, CI).
#pragma once

#include <chrono>
#include <cstdio>

namespace fesph {

class Progress {
 public:
  Progress(double end_time, bool enabled);
  /// Report the state after a step; draws at most a few times a second.
  void update(double time, long step, double dt);
  /// Finish the bar line.
  void finish();

 private:
  double end_time_;
  bool enabled_, tty_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  int last_percent_ = -1;
};

}  // namespace fesph
