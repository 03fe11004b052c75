// SPDX-License-Identifier: MIT
#include "core/sph/neighbours.hpp"

#include "core/common/omp_threads.hpp"

#include <algorithm>
#include <cmath>

namespace fesph {

namespace {

/// Compressed rows built in parallel without atomics: each thread takes one contiguous block
/// of rows, collects them in its own buffer, and copies the buffer to its place once the
/// row lengths are known. The result is the same for any number of threads.
/// collect(i, buf) appends row i (already in its final order) to buf.
template <class Collect>
void buildRows(std::size_t n, Collect&& collect, std::vector<std::vector<int>>& thread_buf,
               std::vector<std::size_t>& count, NeighbourList& out) {
  thread_buf.resize(static_cast<std::size_t>(maxThreads()));
  count.assign(n, 0);
  out.offset.assign(n + 1, 0);
#pragma omp parallel
  {
    const std::size_t nt = static_cast<std::size_t>(teamSize());
    const std::size_t t = static_cast<std::size_t>(threadId());
    const std::size_t begin = n * t / nt, end = n * (t + 1) / nt;
    std::vector<int>& buf = thread_buf[t];
    buf.clear();
    for (std::size_t i = begin; i < end; ++i) {
      const std::size_t before = buf.size();
      collect(i, buf);
      count[i] = buf.size() - before;
    }
#pragma omp barrier
#pragma omp single
    {
      for (std::size_t i = 0; i < n; ++i) out.offset[i + 1] = out.offset[i] + count[i];
      out.index.resize(out.offset[n]);
    }
    std::copy(buf.begin(), buf.end(), out.index.begin() + static_cast<std::ptrdiff_t>(out.offset[begin]));
  }
}

/// The candidates j of each row i that pass |x_i - x_j| < r_i + r_j: term for term the test of
/// the fresh searches (r = h for SPH pairs, the contact radii for contact pairs), so a Verlet
/// list filtered here gives their lists bit for bit.
void filterCandidates(const std::vector<Vec3>& x, const std::vector<double>& r,
                      const NeighbourList& cand, std::vector<std::vector<int>>& thread_buf,
                      std::vector<std::size_t>& count, NeighbourList& out) {
  buildRows(
      x.size(),
      [&](std::size_t i, std::vector<int>& buf) {
        for (std::size_t k = cand.offset[i]; k < cand.offset[i + 1]; ++k) {
          const int j = cand.index[k];
          const double reach = r[i] + r[j];
          if ((x[i] - x[j]).squaredNorm() < reach * reach) buf.push_back(j);
        }
      },
      thread_buf, count, out);
}

}  // namespace

std::uint64_t CellGrid::bucketOf(std::int64_t ix, std::int64_t iy, std::int64_t iz) const {
  // large odd multipliers (Teschner et al. 2003) mix the three cell indices
  const std::uint64_t key = static_cast<std::uint64_t>(ix) * 73856093ULL ^
                            static_cast<std::uint64_t>(iy) * 19349663ULL ^
                            static_cast<std::uint64_t>(iz) * 83492791ULL;
  return key & mask_;
}

int CellGrid::nearbyBuckets(const Vec3& p, std::uint64_t* out) const {
  const Vec3 c = (p - origin_) * inv_cell_;
  const std::int64_t ix = static_cast<std::int64_t>(std::floor(c.x()));
  const std::int64_t iy = static_cast<std::int64_t>(std::floor(c.y()));
  const std::int64_t iz = static_cast<std::int64_t>(std::floor(c.z()));
  int n = 0;
  for (std::int64_t dz = -1; dz <= 1; ++dz)
    for (std::int64_t dy = -1; dy <= 1; ++dy)
      for (std::int64_t dx = -1; dx <= 1; ++dx) out[n++] = bucketOf(ix + dx, iy + dy, iz + dz);
  std::sort(out, out + n);
  return static_cast<int>(std::unique(out, out + n) - out);
}

void CellGrid::build(const std::vector<Vec3>& x, const std::vector<int>& ids, double cell) {
  sorted_.clear();
  if (ids.empty()) return;
  inv_cell_ = 1.0 / cell;
  origin_ = x[ids[0]];
  for (int i : ids) origin_ = origin_.cwiseMin(x[i]);
  std::uint64_t buckets = 1;
  while (buckets < 2 * ids.size()) buckets <<= 1;  // load factor <= 1/2
  mask_ = buckets - 1;

  // counting sort by bucket; ids are ascending, so each bucket stays ascending
  std::vector<std::uint64_t> key(ids.size());
  start_.assign(buckets + 1, 0);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const Vec3 c = (x[ids[k]] - origin_) * inv_cell_;
    key[k] = bucketOf(static_cast<std::int64_t>(std::floor(c.x())),
                      static_cast<std::int64_t>(std::floor(c.y())),
                      static_cast<std::int64_t>(std::floor(c.z())));
    ++start_[key[k] + 1];
  }
  for (std::uint64_t b = 0; b < buckets; ++b) start_[b + 1] += start_[b];
  sorted_.resize(ids.size());
  std::vector<std::size_t> fill(start_.begin(), start_.end() - 1);
  for (std::size_t k = 0; k < ids.size(); ++k) sorted_[fill[key[k]]++] = ids[k];
}

void NeighbourSearch::sphNeighbours(const std::vector<Vec3>& x, const std::vector<double>& h,
                                    const std::vector<int>& body, NeighbourList& out) {
  const std::size_t n = x.size();
  int n_bodies = 0;
  for (int b : body) n_bodies = std::max(n_bodies, b + 1);
  ids_.resize(static_cast<std::size_t>(n_bodies));
  for (auto& v : ids_) v.clear();
  std::vector<double> h_max(static_cast<std::size_t>(n_bodies), 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    ids_[body[i]].push_back(static_cast<int>(i));
    h_max[body[i]] = std::max(h_max[body[i]], h[i]);
  }
  grids_.resize(static_cast<std::size_t>(n_bodies));
  for (int b = 0; b < n_bodies; ++b) grids_[b].build(x, ids_[b], 2.0 * h_max[b]);

  buildRows(
      n,
      [&](std::size_t i, std::vector<int>& buf) {
        const std::size_t first = buf.size();
        const Vec3 xi = x[i];
        const double hi = h[i];
        grids_[body[i]].forEachCandidate(xi, [&](int j) {
          const double support = hi + h[j];  // 2 h_ij
          if (j != static_cast<int>(i) && (xi - x[j]).squaredNorm() < support * support)
            buf.push_back(j);
        });
        std::sort(buf.begin() + static_cast<std::ptrdiff_t>(first), buf.end());
      },
      thread_index_, count_, out);
}

bool NeighbourSearch::Verlet::update(const std::vector<Vec3>& x, const std::vector<double>& r,
                                     const std::vector<int>& body, double skin, bool per_body) {
  const std::size_t n = x.size(), n_built = x_built.size();
  // A pair inside its range now was inside the widened one at the build as long as no
  // particle moved plus grew by more than its margin skin/2 r_built (triangle inequality);
  // 0.99 of it leaves room for round-off in this test. Particles appended since the build
  // (conversions) keep the list if the others kept their bodies: they get their rows then.
  const bool appended = n > n_built && n_built > 0 &&
                        std::equal(body_built.begin(), body_built.end(), body.begin());
  bool rebuild = !(skin > 0) || (n != n_built && !appended) || (n == n_built && body != body_built);
  if (!rebuild) {
    // The motion is measured relative to a translation u shared by all the particles that can
    // pair (each body for SPH pairs, everyone for pairs across bodies): a pair's distance
    // changes by at most |d_i - u| + |d_j - u| for any common u, so a body's particles
    // flying on together force fewer builds (115 -> 86 over 344 steps late in the four-plate
    // quick run). u is the centre of the displacements' box.
    std::size_t n_groups = 1;
    if (per_body)
      for (std::size_t i = 0; i < n_built; ++i)
        n_groups = std::max(n_groups, static_cast<std::size_t>(body[i]) + 1);
    std::vector<Vec3> lo(n_groups, Vec3::Constant(1e300)), hi(n_groups, Vec3::Constant(-1e300));
    for (std::size_t i = 0; i < n_built; ++i) {
      const std::size_t g = per_body ? static_cast<std::size_t>(body[i]) : 0;
      lo[g] = lo[g].cwiseMin(x[i] - x_built[i]);
      hi[g] = hi[g].cwiseMax(x[i] - x_built[i]);
    }
    std::vector<Vec3> shift(n_groups);
    for (std::size_t g = 0; g < n_groups; ++g) shift[g] = 0.5 * (lo[g] + hi[g]);
    const long nb = static_cast<long>(n_built);
#pragma omp parallel for schedule(static) reduction(|| : rebuild)
    for (long i = 0; i < nb; ++i) {
      const Vec3& u = shift[per_body ? static_cast<std::size_t>(body[i]) : 0];
      const double drift = (x[i] - x_built[i] - u).norm() + std::max(0.0, r[i] - r_built[i]);
      if (!(drift <= 0.99 * 0.5 * skin * r_built[i])) rebuild = true;
    }
  }
  if (rebuild) {
    r_wide.resize(n);
    for (std::size_t i = 0; i < n; ++i) r_wide[i] = (1.0 + 0.5 * std::max(skin, 0.0)) * r[i];
    x_built = x;
    r_built = r;
    body_built = body;
    ++builds;
    return true;
  }
  if (appended) {
    x_built.insert(x_built.end(), x.begin() + static_cast<std::ptrdiff_t>(n_built), x.end());
    r_built.insert(r_built.end(), r.begin() + static_cast<std::ptrdiff_t>(n_built), r.end());
    r_wide.resize(n);
    for (std::size_t i = n_built; i < n; ++i) r_wide[i] = (1.0 + 0.5 * skin) * r[i];
    body_built = body;
  }
  return false;
}

void NeighbourSearch::appendCandidates(Verlet& v, std::size_t n_old, bool cross) {
  // The triangle inequality holds whatever position each particle was built at, so a new
  // particle is built at its birth position and paired with the others at theirs: the
  // candidates are then the pairs a fresh build would give if each particle had stayed where
  // it was built, and every later drift check measures from there.
  const std::size_t n = v.x_built.size();
  const std::vector<int>& body = v.body_built;
  // One grid of the built positions: per body that got particles, or one over all (cross).
  int n_grids = 1;
  if (!cross)
    for (int b : body) n_grids = std::max(n_grids, b + 1);
  const auto grid_of = [&](std::size_t i) { return cross ? 0 : body[i]; };
  std::vector<char> grown(static_cast<std::size_t>(n_grids), 0);
  for (std::size_t i = n_old; i < n; ++i) grown[grid_of(i)] = 1;
  ids_.resize(static_cast<std::size_t>(n_grids));
  for (auto& ids : ids_) ids.clear();
  std::vector<double> r_max(static_cast<std::size_t>(n_grids), 0.0);
  for (std::size_t i = 0; i < n; ++i)
    if (grown[grid_of(i)]) {
      ids_[grid_of(i)].push_back(static_cast<int>(i));
      r_max[grid_of(i)] = std::max(r_max[grid_of(i)], v.r_wide[i]);
    }
  grids_.resize(static_cast<std::size_t>(n_grids));
  for (int g = 0; g < n_grids; ++g)
    if (grown[g]) grids_[g].build(v.x_built, ids_[g], 2.0 * r_max[g]);

  // All partners of each new particle, with the fresh search's test on the built positions.
  // A row keeps its partners above it only (cross) or all (same body); a new particle joins
  // the rows of its old partners at their ends (it is larger than anything in them).
  std::vector<std::vector<int>> rows(n - n_old);
  std::vector<std::pair<int, int>> joins;  // (old partner, new particle), new ones ascending
  std::vector<std::size_t> extra(n_old, 0);
  for (std::size_t i = n_old; i < n; ++i) {
    std::vector<int>& row = rows[i - n_old];
    const Vec3 xi = v.x_built[i];
    const double ri = v.r_wide[i];
    grids_[grid_of(i)].forEachCandidate(xi, [&](int j) {
      const double reach = ri + v.r_wide[j];
      if (j != static_cast<int>(i) && (body[j] != body[i]) == cross &&
          (xi - v.x_built[j]).squaredNorm() < reach * reach)
        row.push_back(j);
    });
    std::sort(row.begin(), row.end());
    for (int j : row)
      if (static_cast<std::size_t>(j) < n_old) {
        joins.emplace_back(j, static_cast<int>(i));
        ++extra[j];
      }
    if (cross) row.erase(row.begin(), std::upper_bound(row.begin(), row.end(), static_cast<int>(i)));
  }
  const NeighbourList& old = v.candidates;
  std::vector<std::size_t> offset(n + 1, 0);
  for (std::size_t i = 0; i < n_old; ++i)
    offset[i + 1] = offset[i] + (old.offset[i + 1] - old.offset[i]) + extra[i];
  for (std::size_t i = n_old; i < n; ++i) offset[i + 1] = offset[i] + rows[i - n_old].size();
  std::vector<int> index(offset[n]);
  std::vector<std::size_t> fill(n_old);
  for (std::size_t i = 0; i < n_old; ++i)
    fill[i] = static_cast<std::size_t>(
        std::copy(old.index.begin() + static_cast<std::ptrdiff_t>(old.offset[i]),
                  old.index.begin() + static_cast<std::ptrdiff_t>(old.offset[i + 1]),
                  index.begin() + static_cast<std::ptrdiff_t>(offset[i])) -
        index.begin());
  for (const auto& [j, i] : joins) index[fill[j]++] = i;
  for (std::size_t i = n_old; i < n; ++i)
    std::copy(rows[i - n_old].begin(), rows[i - n_old].end(),
              index.begin() + static_cast<std::ptrdiff_t>(offset[i]));
  v.candidates.offset.swap(offset);
  v.candidates.index.swap(index);
}

void NeighbourSearch::sphNeighboursVerlet(const std::vector<Vec3>& x, const std::vector<double>& h,
                                          const std::vector<int>& body, double skin,
                                          NeighbourList& out) {
  const std::size_t n = x.size(), n_old = sph_.x_built.size();
  if (sph_.update(x, h, body, skin, true))
    sphNeighbours(x, sph_.r_wide, body, sph_.candidates);
  else if (n > n_old)
    appendCandidates(sph_, n_old, false);
  filterCandidates(x, h, sph_.candidates, thread_index_, count_, out);
}

void NeighbourSearch::crossBodyRows(const std::vector<Vec3>& x, const std::vector<double>& r,
                                    const std::vector<int>& body, NeighbourList& rows) {
  const std::size_t n = x.size();
  ids_.resize(1);
  ids_[0].resize(n);
  double r_max = 0;
  for (std::size_t i = 0; i < n; ++i) {
    ids_[0][i] = static_cast<int>(i);
    r_max = std::max(r_max, r[i]);
  }
  if (n == 0 || !(r_max > 0)) {
    rows.offset.assign(n + 1, 0);
    rows.index.clear();
    return;
  }
  grids_.resize(1);
  grids_[0].build(x, ids_[0], 2.0 * r_max);
  buildRows(
      n,
      [&](std::size_t i, std::vector<int>& buf) {
        const std::size_t first = buf.size();
        grids_[0].forEachCandidate(x[i], [&](int j) {
          const double reach = r[i] + r[j];
          if (j > static_cast<int>(i) && body[j] != body[i] &&
              (x[i] - x[j]).squaredNorm() < reach * reach)
            buf.push_back(j);
        });
        std::sort(buf.begin() + static_cast<std::ptrdiff_t>(first), buf.end());
      },
      thread_index_, count_, rows);
}

namespace {

void rowsToPairs(const NeighbourList& rows, std::vector<std::pair<int, int>>& out) {
  out.clear();
  out.reserve(rows.pairs());
  for (std::size_t i = 0; i + 1 < rows.offset.size(); ++i)
    for (std::size_t k = rows.offset[i]; k < rows.offset[i + 1]; ++k)
      out.emplace_back(static_cast<int>(i), rows.index[k]);
}

}  // namespace

void NeighbourSearch::crossBodyPairs(const std::vector<Vec3>& x, const std::vector<double>& r,
                                     const std::vector<int>& body,
                                     std::vector<std::pair<int, int>>& out) {
  crossBodyRows(x, r, body, rows_);
  rowsToPairs(rows_, out);
}

void NeighbourSearch::crossBodyPairsVerlet(const std::vector<Vec3>& x, const std::vector<double>& r,
                                           const std::vector<int>& body, double skin,
                                           std::vector<std::pair<int, int>>& out) {
  const std::size_t n = x.size(), n_old = contact_.x_built.size();
  if (contact_.update(x, r, body, skin, false))
    crossBodyRows(x, contact_.r_wide, body, contact_.candidates);
  else if (n > n_old)
    appendCandidates(contact_, n_old, true);
  filterCandidates(x, r, contact_.candidates, thread_index_, count_, rows_);
  rowsToPairs(rows_, out);
}

void NeighbourSearch::mirrorRows(const std::vector<Vec3>& x, const std::vector<double>& r,
                                 const std::vector<int>& body, const Reflection& image,
                                 bool same_body, NeighbourList& out) {
  const std::size_t n = x.size();
  double r_max = 0;
  for (double ri : r) r_max = std::max(r_max, ri);
  // |x_i - M x_j| >= |d_i + d_j| on each flipped axis (d: signed distance to its plane), so a
  // pair needs both points within r_i + r_j <= 2 r_max of every plane of the image.
  const auto near_planes = [&](std::size_t i) {
    for (int a = 0; a < 3; ++a)
      if (image.flip[a] && !(std::abs(2.0 * x[i][a] - image.twice_position[a]) < 4.0 * r_max))
        return false;
    return true;
  };
  mirror_ids_.clear();
  for (std::size_t i = 0; i < n; ++i)
    if (near_planes(i)) mirror_ids_.push_back(static_cast<int>(i));
  if (mirror_ids_.empty() || !(r_max > 0)) {
    out.offset.assign(n + 1, 0);
    out.index.clear();
    return;
  }
  mirror_grid_.build(x, mirror_ids_, 2.0 * r_max);
  buildRows(
      n,
      [&](std::size_t i, std::vector<int>& buf) {
        if (!near_planes(i)) return;
        const std::size_t first = buf.size();
        // the partners of i's image are the points whose image is a partner of i
        mirror_grid_.forEachCandidate(image.point(x[i]), [&](int j) {
          const bool take = same_body ? body[j] == body[i]
                                      : body[j] != body[i] && j > static_cast<int>(i);
          const double reach = r[i] + r[j];
          if (take && (x[i] - image.point(x[j])).squaredNorm() < reach * reach) buf.push_back(j);
        });
        std::sort(buf.begin() + static_cast<std::ptrdiff_t>(first), buf.end());
      },
      thread_index_, count_, out);
}

void sphNeighboursBruteForce(const std::vector<Vec3>& x, const std::vector<double>& h,
                             const std::vector<int>& body, NeighbourList& out) {
  const std::size_t n = x.size();
  out.offset.assign(n + 1, 0);
  out.index.clear();
  for (std::size_t i = 0; i < n; ++i) {
    for (std::size_t j = 0; j < n; ++j) {
      const double support = h[i] + h[j];
      if (j != i && body[j] == body[i] && (x[i] - x[j]).squaredNorm() < support * support)
        out.index.push_back(static_cast<int>(j));
    }
    out.offset[i + 1] = out.index.size();
  }
}

}  // namespace fesph
