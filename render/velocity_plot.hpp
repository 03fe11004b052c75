// SPDX-License-Identifier: MIT
// Projectile velocity history plots (the paper's Fig. 5) from one or more runs' history.csv,
// drawn with VTK charts on the off-screen window.
#pragma once

#include "render/plate_images.hpp"

#include <string>
#include <utility>
#include <vector>

namespace fesph {

enum class VelocityMeasure {
  Speed,      ///< |v| of the body's mean velocity
  MinusVz,    ///< -v_z: the speed along -z, the usual direction of flight
};

namespace render_detail {

/// A body's velocity over a run, one entry per history row.
struct VelocitySeries {
  std::vector<double> t_us;  ///< time, µs
  std::vector<double> v;     ///< |v| or -v_z (VelocityMeasure), m/s
};

/// The bodies whose velocity is drawn for a run by default: its projectiles (from scene.toml
/// beside `csv`), else its first body; empty when neither is known.
std::vector<std::string> plottedBodies(const std::string& csv);

/// The <body>_vx, _vy, _vz columns of one history.csv; `body` empty: the run's first projectile
/// (from scene.toml beside the file), else its first body. A row cut short (the last row of a
/// stopped run) is skipped. Throws RunError for a missing file or column, or no row.
VelocitySeries readVelocity(const std::string& csv, std::string body, VelocityMeasure measure);

}  // namespace render_detail

/// Colour of the k-th curve (0-255 RGB; the test looks for these pixels).
void curveColour(int k, unsigned char rgb[3]);

/// One curve per (label, history.csv) pair, time in µs against velocity in m/s, with a legend.
/// `body`: the body whose <body>_vx,_vy,_vz columns are plotted; empty: each run's projectiles
/// (plottedBodies), a curve each, labelled "label: body" where a run has more than one. Only
/// options.width and options.height are used. Returns `out_png`. Throws RunError (missing file
/// or column).
std::string renderVelocityPlot(
    const std::vector<std::pair<std::string, std::string>>& label_and_history_csv,
    const std::string& body, const std::string& out_png, const ImageOptions& options = {},
    VelocityMeasure measure = VelocityMeasure::Speed);

}  // namespace fesph
