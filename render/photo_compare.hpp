// SPDX-License-Identifier: MIT
// The file side of `fesph compare`: photographs read through VTK (PNG, JPEG, TIFF, BMP, PNM),
// the simulated plate read back from a run folder, and the side-by-side and overlay images.
#pragma once

#include "core/analysis/photo_holes.hpp"

#include <string>

namespace fesph {

/// Brightness (Rec. 601 luma of RGB, or the grey channel) in [0, 1], row 0 at the top.
/// Throws InputError when the file cannot be read as an image.
GrayImage readPhoto(const std::string& path);

/// Write `image` (row 0 at the top) as an 8-bit grey PNG. Throws RunError.
void writeGrayPng(const GrayImage& image, const std::string& path);

/// Body `body` (named `name`) of the run in `run_dir` at the output step nearest to `time`
/// (< 0: the last), as the photograph would show it (half models mirrored on y = 0).
/// A plate made of particles is measured from its particles (simulatedParticlePlate).
/// `*step_time` gets the time of the step read. Throws RunError, also for a body with neither
/// an element nor a particle there.
SimulatedPlate readSimulatedPlate(const std::string& run_dir, double time, int body,
                                  const std::string& name, bool half,
                                  double* step_time = nullptr);

/// Side by side, on the photograph's grid and scale: the photograph with its holes outlined in
/// red | the simulated plate (grey, its extent) with its holes in black, outlined in blue.
void writeSideBySide(const GrayImage& photo, const PhotoSegmentation& seg,
                     const HoleComparison& cmp, const SimulatedPlate& plate,
                     const std::string& path);

/// The photograph dimmed, hole pixels of both maps green, of the photograph only red, of the
/// simulation only blue.
void writeOverlay(const GrayImage& photo, const PhotoSegmentation& seg, const HoleComparison& cmp,
                  const std::string& path);

}  // namespace fesph
