// SPDX-License-Identifier: MIT
#include "core/mesh/tet_faces.hpp"

#include <algorithm>

namespace fesph {

std::vector<TetFaceEntry> sortedTetFaces(const std::vector<std::array<int, 4>>& tets) {
  std::vector<TetFaceEntry> faces;
  faces.reserve(4 * tets.size());
  for (std::size_t t = 0; t < tets.size(); ++t)
    for (int k = 0; k < 4; ++k) {
      std::array<int, 3> key;
      for (int m = 0, n = 0; m < 4; ++m)
        if (m != k) key[n++] = tets[t][m];
      std::sort(key.begin(), key.end());
      faces.push_back({key, static_cast<int>(t), k});
    }
  std::sort(faces.begin(), faces.end(), [](const TetFaceEntry& a, const TetFaceEntry& b) {
    return a.key != b.key ? a.key < b.key : a.tet < b.tet;
  });
  return faces;
}

}  // namespace fesph
