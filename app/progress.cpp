// SPDX-License-Identifier: MIT
#include "app/progress.hpp"

#include <algorithm>
#include <string>
#include <unistd.h>

namespace fesph {

namespace {

std::string clock(double seconds) {
  const long s = static_cast<long>(seconds + 0.5);
  char buf[32];
  std::snprintf(buf, sizeof buf, "%ld:%02ld:%02ld", s / 3600, (s / 60) % 60, s % 60);
  return buf;
}

}  // namespace

Progress::Progress(double end_time, bool enabled)
    : end_time_(end_time), enabled_(enabled), tty_(isatty(fileno(stderr)) != 0),
      start_(std::chrono::steady_clock::now()), last_draw_(start_) {}

void Progress::update(double time, long step, double dt) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  const double frac = std::clamp(time / end_time_, 0.0, 1.0);
  const int percent = static_cast<int>(100 * frac);
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double eta = frac > 0 ? elapsed * (1 - frac) / frac : 0.0;
  if (tty_) {
    if (std::chrono::duration<double>(now - last_draw_).count() < 0.2 && frac < 1) return;
    last_draw_ = now;
    const int width = 30, filled = static_cast<int>(width * frac);
    std::fprintf(stderr, "\r[%s%s] %3d%%  t = %.4g / %.4g s  step %ld  dt %.3g s  ETA %s ",
                 std::string(filled, '#').c_str(), std::string(width - filled, ' ').c_str(),
                 percent, time, end_time_, step, dt, clock(eta).c_str());
    std::fflush(stderr);
  } else if (percent / 10 != last_percent_ / 10) {
    last_percent_ = percent;
    std::fprintf(stderr, "%3d%%  t = %.4g / %.4g s  step %ld  dt %.3g s  elapsed %s  ETA %s\n",
                 percent, time, end_time_, step, dt, clock(elapsed).c_str(), clock(eta).c_str());
  }
}

void Progress::finish() {
  if (enabled_ && tty_) std::fprintf(stderr, "\n");
}

}  // namespace fesph
