// SPDX-License-Identifier: MIT
// Neighbour search for the SPH layer: a hashed uniform cell list (O(N)), SPH pairs within one
// body (from scratch, or through a Verlet list rebuilt only when many particles moved enough;
// a few are re-seated), contact pairs across bodies, and a brute-force reference.
#pragma once

#include "core/common/reflection.hpp"
#include "core/common/thread_buffer.hpp"
#include "core/common/types.hpp"

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace fesph {

/// Neighbour lists in compressed rows: the neighbours of particle i are
/// index[offset[i]] .. index[offset[i+1] - 1], ascending, i itself excluded.
struct NeighbourList {
  std::vector<std::size_t> offset;  ///< size particles + 1
  std::vector<int> index;           ///< neighbour ids
  std::size_t pairs() const { return index.size(); }
};

/// Uniform grid of cubic cells over a set of points, stored as a hash table of buckets so that
/// its memory is O(points) however far debris flies apart. A bucket may hold points of
/// several cells (hash collisions); callers filter by distance, which is the real test.
class CellGrid {
 public:
  /// Sort the points `ids` (ascending) of `x` into cells of edge `cell` (m, > 0).
  void build(const std::vector<Vec3>& x, const std::vector<int>& ids, double cell);

  /// Appends to `out` the candidates j of position p for which keep(j) holds: the points of
  /// the 27 cells around p (and the points sharing their buckets), bucket by bucket in no
  /// fixed order (callers sort what they keep), ids ascending within a bucket. Every
  /// candidate is written and the end moves on past those kept: whether one is kept is a coin
  /// toss to the branch predictor (~1 in 6 of the 27 cells' points).
  template <class Keep>
  void appendCandidates(const Vec3& p, std::vector<int>& out, Keep&& keep) const {
    std::uint64_t buckets[27];
    const int n = nearbyBuckets(p, buckets);
    std::size_t total = 0;
    for (int k = 0; k < n; ++k) total += start_[buckets[k] + 1] - start_[buckets[k]];
    std::size_t kept = out.size();
    out.resize(kept + total);
    for (int k = 0; k < n; ++k)
      for (std::size_t s = start_[buckets[k]]; s < start_[buckets[k] + 1]; ++s) {
        out[kept] = sorted_[s];
        kept += keep(sorted_[s]) ? 1 : 0;
      }
    out.resize(kept);
  }

  bool empty() const { return sorted_.empty(); }
  /// Bytes of its storage.
  std::size_t bytes() const;

 private:
  std::uint64_t bucketOf(std::int64_t ix, std::int64_t iy, std::int64_t iz) const;
  /// Distinct buckets of the 27 cells around p; returns their count.
  int nearbyBuckets(const Vec3& p, std::uint64_t* out) const;

  double inv_cell_ = 0;
  Vec3 origin_ = Vec3::Zero();
  std::uint64_t mask_ = 0;
  std::vector<std::size_t> start_;  ///< bucket -> first slot in sorted_ (size buckets + 1)
  std::vector<int> sorted_;         ///< point ids grouped by bucket
};

/// Rebuilds neighbour lists and contact pairs each step, keeping its storage between calls.
/// Results do not depend on the number of threads.
class NeighbourSearch {
 public:
  /// SPH neighbours: pairs of the same body with |x_i - x_j| < 2 h_ij, h_ij = (h_i + h_j)/2.
  /// One grid per body with cells of 2 max(h) of that body.
  void sphNeighbours(const std::vector<Vec3>& x, const std::vector<double>& h,
                     const std::vector<int>& body, NeighbourList& out);

  /// sphNeighbours through a Verlet list: candidate pairs within the support widened by
  /// (1 + skin/2), rebuilt only when more than 1 in 8 particles have moved (relative to their
  /// body's median translation), or their h grown, by more than their share of the skin since
  /// they were built (or the particles changed other than by particles appended at the end);
  /// fewer such particles, and the appended ones, are paired again where they are. The candidates are filtered with sphNeighbours' own test at
  /// every call, so `out` is bit for bit the list a fresh sphNeighbours gives: when the
  /// candidates were built never changes a result.
  void sphNeighboursVerlet(const std::vector<Vec3>& x, const std::vector<double>& h,
                           const std::vector<int>& body, double skin, NeighbourList& out);
  /// Builds of the Verlet candidate list so far.
  long verletBuilds() const { return sph_.builds; }
  /// Particles re-seated in the Verlet lists (SPH and contact) so far instead of a build.
  long verletReseats() const { return sph_.reseats + contact_.reseats; }

  /// Contact candidates: pairs (i < j) of different bodies with |x_i - x_j| < r_i + r_j,
  /// sorted by (i, j). One grid over all points with cells of 2 max(r).
  void crossBodyPairs(const std::vector<Vec3>& x, const std::vector<double>& r,
                      const std::vector<int>& body, std::vector<std::pair<int, int>>& out);
  /// crossBodyPairs through a Verlet list, as sphNeighboursVerlet (r in the place of h): bit
  /// for bit the pairs crossBodyPairs gives.
  void crossBodyPairsVerlet(const std::vector<Vec3>& x, const std::vector<double>& r,
                            const std::vector<int>& body, double skin,
                            std::vector<std::pair<int, int>>& out);
  /// Builds of the contact Verlet list so far.
  long contactVerletBuilds() const { return contact_.builds; }

  /// Pairs of the points with the mirror images of the points: row i holds the j (ascending)
  /// with |x_i - M x_j| < r_i + r_j, M = `image`; of the same body, i itself included
  /// (same_body), or of another body with j > i (!same_body: a pair and its mirror are one
  /// interaction). Only the points
  /// within 2 max(r) of the image's planes are searched; built afresh at every call.
  void mirrorRows(const std::vector<Vec3>& x, const std::vector<double>& r,
                  const std::vector<int>& body, const Reflection& image, bool same_body,
                  NeighbourList& out);

  /// mirrorRows through a Verlet list, one for each image (`which`) and kind of pair
  /// (same_body), as sphNeighboursVerlet: candidates within the ranges widened by
  /// (1 + skin/2), filtered at every call with mirrorRows' own tests, so `out` is bit for bit
  /// the rows mirrorRows gives. Built afresh when a point near the planes has moved (relative
  /// to its body's translation along the planes, or everyone's for pairs across bodies) or
  /// grown by more than its share of the skin, when an appended point is wider than the
  /// widest or on the other side, or when the points are not all on one side of each plane;
  /// other appended points are paired in.
  void mirrorRowsVerlet(const std::vector<Vec3>& x, const std::vector<double>& r,
                        const std::vector<int>& body, const Reflection& image, bool same_body,
                        std::size_t which, double skin, NeighbourList& out);
  /// Builds of the mirror images' Verlet lists so far.
  long mirrorVerletBuilds() const {
    long builds = 0;
    for (const MirrorVerlet& m : mirror_verlet_) builds += m.lists.builds;
    return builds;
  }

  /// Bytes of the storage kept between calls (Verlet lists, grids, scratch).
  std::size_t bytes() const;

  /// Forget the Verlet candidates (the particles were renumbered): the next calls build
  /// them afresh.
  void forgetCandidates() {
    sph_.x_built.clear();
    contact_.x_built.clear();
    for (MirrorVerlet& m : mirror_verlet_) m.lists.x_built.clear();
  }

 private:
  /// Candidate pairs within the ranges r widened by (1 + skin/2), and the state they were
  /// built from.
  struct Verlet {
    NeighbourList candidates;
    std::vector<Vec3> x_built;
    std::vector<double> r_built, r_wide;
    std::vector<int> body_built;
    long builds = 0;
    /// The few particles past their margin at the last update, ascending, when they were
    /// re-seated instead of rebuilding the list (pairAgain gives them their rows).
    std::vector<int> reseated;
    long reseats = 0;
    std::size_t pairs_added = 0;  ///< candidate pairs added by pairAgain since the build
    // Scratch kept between steps (a fresh allocation of this size faults its pages in anew):
    NeighbourList merged;                   ///< pairAgain's merged rows, swapped with candidates
    std::vector<std::size_t> add_offset;    ///< pairAgain's additions by row (compressed rows)
    std::vector<int> add;
    std::vector<std::vector<double>> comp;  ///< update's sampled displacements, by group and axis
    std::vector<char> is_past;              ///< update's particles past their margin
    /// Whether the candidates must be built afresh (then the built state is taken from x,
    /// r and body); otherwise appended particles are added to the built state, and a few
    /// particles past their margin (up to 1 in kReseatShare) are re-seated (`reseated`).
    /// per_body: pairs only form within a body (its translation is then its own).
    bool update(const std::vector<Vec3>& x, const std::vector<double>& r,
                const std::vector<int>& body, double skin, bool per_body);
    /// Add the pairs (row, partner) of `found` to the candidates' rows, each row staying
    /// ascending; returns how many.
    std::size_t addPairs(const std::vector<std::vector<std::pair<int, int>>>& found);
    std::size_t bytes() const;
  };
  /// The Verlet list of one mirror image's rows (mirrorRowsVerlet).
  struct MirrorVerlet {
    Verlet lists;      ///< candidates and the state they were built from (no re-seats)
    Reflection image;  ///< the image the candidates were built for
    double r_wide_max = 0;
    bool positive[3] = {true, true, true};  ///< the side of each plane the points are on
    bool one_side = false;                  ///< all built points on that side (or on it)
    std::vector<int> band;  ///< built points within 2 max(r_wide) of every plane, ascending
    /// The appended points' pairs (row, partner), for Verlet::addPairs.
    std::vector<std::vector<std::pair<int, int>>> added = {{}};
    std::size_t bytes() const;
  };
  /// Pair the particles `again` (ascending) at their built positions with all the others:
  /// the candidate pairs they lack are added, the rows staying ascending (same body: full
  /// rows; cross: a pair in the row of its lower partner). Rows for particles appended since
  /// the last build are added first.
  void pairAgain(Verlet& v, const std::vector<int>& again, bool cross);
  /// pairAgain for the particles from n_old on (appended) and the re-seated ones.
  void pairAgain(Verlet& v, std::size_t n_old, bool cross);
  /// crossBodyPairs as rows of the partners j > i.
  void crossBodyRows(const std::vector<Vec3>& x, const std::vector<double>& r,
                     const std::vector<int>& body, NeighbourList& rows);

  std::vector<CellGrid> grids_;
  CellGrid mirror_grid_;                            ///< points near the symmetry planes
  std::vector<int> mirror_ids_;
  std::vector<std::size_t> mirror_work_;            ///< mirrorRows' rows near the planes, prefix
  std::vector<std::vector<int>> ids_;               ///< per body (or one set), ascending
  std::vector<ThreadBuffer<std::vector<int>>> block_rows_;  ///< each block's rows (buildRows)
  std::vector<std::size_t> count_;
  NeighbourList rows_;                              ///< contact pairs as rows
  Verlet sph_, contact_;
  std::vector<MirrorVerlet> mirror_verlet_;
};

/// O(N^2) reference for sphNeighbours, for tests.
void sphNeighboursBruteForce(const std::vector<Vec3>& x, const std::vector<double>& h,
                             const std::vector<int>& body, NeighbourList& out);

}  // namespace fesph
