// SPDX-License-Identifier: MIT
// Exterior surfaces of the element bodies, kept up to date as elements erode or convert, and
// the contact search buffers reused every step. (Owned by the contact layer; see core/contact/.)
#pragma once

#include "core/common/thread_buffer.hpp"
#include "core/common/types.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace fesph {

/// One triangle of the tet meshes, shared by one element or two.
struct FaceRecord {
  std::array<int, 3> key = {-1, -1, -1};  ///< node ids, ascending
  std::array<int, 2> elem = {-1, -1};     ///< adjacent elements; elem[1] = -1 on the mesh boundary
  int exterior = -1;                      ///< index in Surfaces::exterior, -1 if not exterior
};

/// A face with exactly one live adjacent element, oriented out of that element:
/// (x[1] - x[0]) x (x[2] - x[0]) points away from the element's fourth node.
struct ExteriorFace {
  std::array<int, 3> node = {-1, -1, -1};
  int elem = -1;  ///< the live element it bounds
  int body = -1;
  int face = -1;  ///< index in Surfaces::table
};

/// The square of face f's longest edge at positions x (m^2). Searches that need the length
/// take one sqrt of this: sqrt is monotonic and correctly rounded, so that is the longest of
/// the three lengths bit for bit.
inline double longestEdgeSquared(const std::vector<Vec3>& x, const ExteriorFace& f) {
  double longest_sq = 0;
  for (int i = 0; i < 3; ++i)
    longest_sq = std::max(longest_sq, (x[f.node[(i + 1) % 3]] - x[f.node[i]]).squaredNorm());
  return longest_sq;
}

/// Node -> candidate exterior faces of other bodies for one step (CSR), from the broad phase.
struct ContactCandidates {
  std::vector<int> slaves;              ///< active slave nodes by body, in slave-list order
  std::vector<std::size_t> body_begin;  ///< body b: slaves[body_begin[b], body_begin[b + 1])
  std::vector<std::size_t> offset;  ///< candidates of slaves[i]: faces[offset[i], offset[i+1])
  std::vector<int> faces;           ///< exterior face indices, ascending per slave
  std::vector<int> active;          ///< slaves (indices into `slaves`) with candidates, ascending
};

/// Scratch of the contact search and correction, kept so the step allocates nothing.
struct ContactScratch {
  std::vector<Vec3> face_lo, face_hi;         ///< swept, inflated boxes of the exterior faces
  std::vector<double> face_tol;               ///< depth tolerance of each exterior face, m
  std::vector<Vec3> slave_lo, slave_hi;       ///< boxes of the slaves' segments over the step
  std::vector<int> queried;                   ///< slaves near another body's faces, ascending
  std::vector<std::size_t> bucket_offset;     ///< spatial hash buckets -> bucket_faces (CSR)
  std::vector<std::size_t> bucket_fill;       ///< fill cursor of each bucket
  std::vector<int> bucket_faces;
  std::vector<ThreadBuffer<std::vector<std::pair<std::uint64_t, int>>>> thread_cells;  ///< (cell hash, face)
  std::vector<ThreadBuffer<std::vector<int>>> thread_faces;  ///< per-thread candidate lists before merging
  std::vector<int> slave_thread;              ///< thread that searched for each queried slave
  std::vector<std::size_t> slave_start;       ///< where in that thread's list its candidates start
  std::vector<int> contact_face;              ///< face each active slave of a sub-pass hits
};

struct Surfaces {
  /// Every face of the meshes, sorted by key: binary search finds a node triple.
  std::vector<FaceRecord> table;
  /// Faces of element e in the table; face k is the one opposite corner k.
  std::vector<std::array<int, 4>> elem_faces;
  /// Exterior faces of all bodies (order changes as faces come and go).
  std::vector<ExteriorFace> exterior;
  /// Per body: nodes on its exterior faces (order changes as nodes come and go).
  std::vector<std::vector<int>> slave_nodes;
  std::vector<int> node_face_count;  ///< exterior faces touching each node
  std::vector<int> node_slot;        ///< position of a node in its body's slave list, -1: none

  ContactCandidates candidates;
  ContactScratch scratch;
};

}  // namespace fesph
