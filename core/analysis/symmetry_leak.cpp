// SPDX-License-Identifier: MIT
#include "core/analysis/symmetry_leak.hpp"

namespace fesph {

std::vector<SymmetryLeak> particlesAcrossSymmetry(const Model& model,
                                                  const std::vector<SymmetryPlane>& planes) {
  std::vector<SymmetryLeak> leaks;
  const Particles& pa = model.particles;
  double total = 0;
  for (std::size_t i = 0; i < pa.size(); ++i) total += pa.m[i];
  for (const SymmetryPlane& s : planes) {
    // The model's side: where its nodes are (those on the plane count for neither side).
    double side = 0;
    for (const Vec3& x : model.nodes.x) side += x[s.axis] - s.position;
    if (side == 0) continue;
    SymmetryLeak leak;
    leak.plane = &s;
    for (std::size_t i = 0; i < pa.size(); ++i)
      if ((pa.x[i][s.axis] - s.position) * side < 0) {
        ++leak.particles;
        leak.mass += pa.m[i];
      }
    leak.mass_fraction = total > 0 ? leak.mass / total : 0.0;
    leaks.push_back(leak);
  }
  return leaks;
}

}  // namespace fesph
