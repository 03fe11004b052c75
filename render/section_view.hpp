// SPDX-License-Identifier: MIT
// Section view of the whole scene on the symmetry plane y = 0 (the paper's Fig. 4): elements
// coloured by a cell field, particles near the plane as spheres, flight from left to right.
#pragma once

#include "render/plate_images.hpp"

#include <string>

namespace fesph {

/// Section y = 0 of every body at the series step nearest to `time` (< 0: the last), seen from
/// -y with +x up and the -z flight direction to the right. A true cut (vtkCutter), so holes show
/// as gaps; half models are cut a hair inside their y = 0 face. Coloured by options.field
/// unless it is "damage" (the ImageOptions default), then by plastic strain; particles within
/// 1.5 radii of the plane in the same colours. Returns `out_png`. Throws RunError.
std::string renderSectionView(const std::string& run_dir, double time, const ImageOptions& options,
                              const std::string& out_png);

}  // namespace fesph
