// SPDX-License-Identifier: MIT
// The debris of a run at one output, read back from its particle series: clumps of free
// particles and the plates they would strike (core/analysis/debris.hpp), as debris.csv.
#pragma once

#include "core/analysis/debris.hpp"
#include "render/plate_images.hpp"

#include <string>
#include <vector>

namespace fesph {

/// The free particles (not tied to an element face) of the series step nearest to `time`
/// (< 0: the last), but for those `plate_particles` lists (indices in that step's series:
/// the plates made of particles, PlateImages::particles). No particle series: none. Throws
/// RunError (unreadable file, a particle array missing).
std::vector<DebrisParticle> readDebris(const std::string& run_dir, double time,
                                       const std::vector<vtkIdType>& plate_particles = {});

/// The plates of `images` as targets (their front faces and extents at the images' time).
std::vector<TargetPlate> targetPlates(const std::vector<PlateImages>& images);

/// Writes OUT_DIR/debris.csv for the output step at `time` (the one the plate images show;
/// their plates are the targets, and a plate made of particles is not its own debris),
/// writeDebrisCsv. Throws RunError.
DebrisSummary writeDebrisTable(const std::string& run_dir, double time,
                               const std::vector<PlateImages>& images, const std::string& out_dir);

}  // namespace fesph
