// SPDX-License-Identifier: MIT
// Mirror symmetry about planes normal to the coordinate axes: the symmetry planes of a half
// (or quarter) model, and the reflections that map the model onto its mirror images.
#pragma once

#include "core/common/types.hpp"

#include <vector>

namespace fesph {

/// A plane of mirror symmetry normal to a coordinate axis: the model is one side of a body
/// symmetric about it, and the solver supplies the other side's effect.
struct SymmetryPlane {
  int axis = 1;           ///< 0, 1, 2 = x, y, z
  double position = 0.0;  ///< m
};

/// A reflection about one or more mutually orthogonal symmetry planes (at most one per axis):
/// x_a -> 2 p_a - x_a on each flipped axis a. Vectors flip those components; a tensor T maps
/// to P T P with P = diag(+-1), so the components with one flipped index change sign.
struct Reflection {
  bool flip[3] = {false, false, false};
  Vec3 twice_position = Vec3::Zero();  ///< 2 p_a on the flipped axes, m

  Vec3 point(const Vec3& x) const {
    Vec3 y = x;
    for (int a = 0; a < 3; ++a)
      if (flip[a]) y[a] = twice_position[a] - x[a];
    return y;
  }
  Vec3 vector(const Vec3& v) const {
    Vec3 y = v;
    for (int a = 0; a < 3; ++a)
      if (flip[a]) y[a] = -v[a];
    return y;
  }
  Mat3 tensor(const Mat3& t) const {
    Mat3 y = t;
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        if (flip[a] != flip[b]) y(a, b) = -t(a, b);
    return y;
  }
};

/// The mirror images of a model cut by `planes` (one per axis): every non-empty combination of
/// the planes, 2^k - 1 reflections for k planes (one for a half model, three for a quarter).
inline std::vector<Reflection> mirrorImages(const std::vector<SymmetryPlane>& planes) {
  std::vector<Reflection> images;
  const unsigned k = static_cast<unsigned>(planes.size());
  for (unsigned subset = 1; subset < (1u << k); ++subset) {
    Reflection r;
    for (unsigned p = 0; p < k; ++p)
      if (subset >> p & 1u) {
        r.flip[planes[p].axis] = true;
        r.twice_position[planes[p].axis] = 2.0 * planes[p].position;
      }
    images.push_back(r);
  }
  return images;
}

}  // namespace fesph
