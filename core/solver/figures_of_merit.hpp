// SPDX-License-Identifier: MIT
// Figures of merit of a run: cost per element-step and per particle-step, the time split by
// phase, the memory the model's arrays hold and the peak resident memory of the process.
#pragma once

#include "core/state/model.hpp"

#include <cstddef>
#include <cstdio>

namespace fesph {

/// Bytes held (vector capacities) by the model's arrays, by part.
struct Footprint {
  std::size_t elements = 0;   ///< element arrays, corner forces, node->corner lists, face table
  std::size_t nodes = 0;      ///< node arrays and nodal scratch
  std::size_t contact = 0;    ///< exterior faces, slave lists, candidates, search scratch
  /// particle arrays, the SPH workspace (neighbour lists) and the particle-face contact's
  /// buffers
  std::size_t particles = 0;
  std::size_t total() const { return elements + nodes + contact + particles; }
};
Footprint modelFootprint(const Model& model);

/// Peak resident memory of this process so far, bytes (getrusage); 0 where unknown.
std::size_t peakResidentBytes();

/// The figures of merit lines of the run summary, from model.timing.
void printFiguresOfMerit(const Model& model, std::FILE* out = stdout);

}  // namespace fesph
