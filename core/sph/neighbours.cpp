// SPDX-License-Identifier: MIT
#include "core/sph/neighbours.hpp"

#include <algorithm>
#include <cmath>

#ifdef _OPENMP
#include <omp.h>
#endif

namespace fesph {

namespace {

int maxThreads() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}

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
#ifdef _OPENMP
    const std::size_t nt = static_cast<std::size_t>(omp_get_num_threads());
    const std::size_t t = static_cast<std::size_t>(omp_get_thread_num());
#else
    const std::size_t nt = 1, t = 0;
#endif
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

void NeighbourSearch::sphNeighboursVerlet(const std::vector<Vec3>& x, const std::vector<double>& h,
                                          const std::vector<int>& body, double skin,
                                          NeighbourList& out) {
  const std::size_t n = x.size(), n_built = x_built_.size();
  // A pair inside the support now was inside the widened one at the build as long as no
  // particle moved plus grew by more than its margin skin/2 h_built (triangle inequality);
  // 0.99 of it leaves room for round-off in this test. Particles appended since the build
  // (conversions) keep the list if the others kept their bodies: they get their rows then.
  const bool appended = n > n_built && n_built > 0 &&
                        std::equal(body_built_.begin(), body_built_.end(), body.begin());
  bool rebuild = !(skin > 0) || (n != n_built && !appended) || (n == n_built && body != body_built_);
  if (!rebuild) {
    const long nb = static_cast<long>(n_built);
#pragma omp parallel for schedule(static) reduction(|| : rebuild)
    for (long i = 0; i < nb; ++i) {
      const double drift = (x[i] - x_built_[i]).norm() + std::max(0.0, h[i] - h_built_[i]);
      if (!(drift <= 0.99 * 0.5 * skin * h_built_[i])) rebuild = true;
    }
  }
  if (rebuild) {
    h_wide_.resize(n);
    for (std::size_t i = 0; i < n; ++i) h_wide_[i] = (1.0 + 0.5 * std::max(skin, 0.0)) * h[i];
    sphNeighbours(x, h_wide_, body, candidates_);
    x_built_ = x;
    h_built_ = h;
    body_built_ = body;
    ++verlet_builds_;
  } else if (appended) {
    appendCandidates(x, h, body, skin);
  }
  buildRows(
      n,
      [&](std::size_t i, std::vector<int>& buf) {
        const Vec3 xi = x[i];
        const double hi = h[i];
        for (std::size_t k = candidates_.offset[i]; k < candidates_.offset[i + 1]; ++k) {
          const int j = candidates_.index[k];
          const double support = hi + h[j];  // the test of sphNeighbours, term for term
          if ((xi - x[j]).squaredNorm() < support * support) buf.push_back(j);
        }
      },
      thread_index_, count_, out);
}

void NeighbourSearch::appendCandidates(const std::vector<Vec3>& x, const std::vector<double>& h,
                                       const std::vector<int>& body, double skin) {
  // The triangle inequality holds whatever position each particle was built at, so a new
  // particle is built at its birth position and paired with the others at theirs: the
  // candidates are then the pairs a fresh build would give if each particle had stayed where
  // it was built, and every later drift check measures from there.
  const std::size_t n = x.size(), n_built = x_built_.size();
  x_built_.insert(x_built_.end(), x.begin() + static_cast<std::ptrdiff_t>(n_built), x.end());
  h_built_.insert(h_built_.end(), h.begin() + static_cast<std::ptrdiff_t>(n_built), h.end());
  h_wide_.resize(n);
  for (std::size_t i = n_built; i < n; ++i) h_wide_[i] = (1.0 + 0.5 * skin) * h[i];
  body_built_ = body;

  // One grid of the built positions for each body that got particles.
  int n_bodies = 0;
  for (int b : body) n_bodies = std::max(n_bodies, b + 1);
  std::vector<char> grown(static_cast<std::size_t>(n_bodies), 0);
  for (std::size_t i = n_built; i < n; ++i) grown[body[i]] = 1;
  ids_.resize(static_cast<std::size_t>(n_bodies));
  for (auto& v : ids_) v.clear();
  std::vector<double> h_max(static_cast<std::size_t>(n_bodies), 0.0);
  for (std::size_t i = 0; i < n; ++i)
    if (grown[body[i]]) {
      ids_[body[i]].push_back(static_cast<int>(i));
      h_max[body[i]] = std::max(h_max[body[i]], h_wide_[i]);
    }
  grids_.resize(static_cast<std::size_t>(n_bodies));
  for (int b = 0; b < n_bodies; ++b)
    if (grown[b]) grids_[b].build(x_built_, ids_[b], 2.0 * h_max[b]);

  // Rows of the new particles, with sphNeighbours' test on the built positions; each new
  // particle also joins the rows of its old candidates (ascending: it is larger than them).
  std::vector<std::vector<int>> rows(n - n_built);
  std::vector<std::size_t> extra(n_built + 1, 0);
  for (std::size_t i = n_built; i < n; ++i) {
    std::vector<int>& row = rows[i - n_built];
    const Vec3 xi = x_built_[i];
    const double hi = h_wide_[i];
    grids_[body[i]].forEachCandidate(xi, [&](int j) {
      const double support = hi + h_wide_[j];
      if (j != static_cast<int>(i) && (xi - x_built_[j]).squaredNorm() < support * support)
        row.push_back(j);
    });
    std::sort(row.begin(), row.end());
    for (int j : row)
      if (static_cast<std::size_t>(j) < n_built) ++extra[j + 1];
  }
  std::vector<std::size_t> offset(n + 1, 0);
  for (std::size_t i = 0; i < n_built; ++i)
    offset[i + 1] = offset[i] + (candidates_.offset[i + 1] - candidates_.offset[i]) + extra[i + 1];
  for (std::size_t i = n_built; i < n; ++i) offset[i + 1] = offset[i] + rows[i - n_built].size();
  std::vector<int> index(offset[n]);
  std::vector<std::size_t> fill(n_built);
  for (std::size_t i = 0; i < n_built; ++i) {
    fill[i] = static_cast<std::size_t>(
        std::copy(candidates_.index.begin() + static_cast<std::ptrdiff_t>(candidates_.offset[i]),
                  candidates_.index.begin() + static_cast<std::ptrdiff_t>(candidates_.offset[i + 1]),
                  index.begin() + static_cast<std::ptrdiff_t>(offset[i])) -
        index.begin());
  }
  for (std::size_t i = n_built; i < n; ++i) {
    const std::vector<int>& row = rows[i - n_built];
    std::copy(row.begin(), row.end(), index.begin() + static_cast<std::ptrdiff_t>(offset[i]));
    for (int j : row)
      if (static_cast<std::size_t>(j) < n_built) index[fill[j]++] = static_cast<int>(i);
  }
  candidates_.offset.swap(offset);
  candidates_.index.swap(index);
}

void NeighbourSearch::crossBodyPairs(const std::vector<Vec3>& x, const std::vector<double>& r,
                                     const std::vector<int>& body,
                                     std::vector<std::pair<int, int>>& out) {
  const std::size_t n = x.size();
  out.clear();
  ids_.resize(1);
  ids_[0].resize(n);
  double r_max = 0;
  for (std::size_t i = 0; i < n; ++i) {
    ids_[0][i] = static_cast<int>(i);
    r_max = std::max(r_max, r[i]);
  }
  if (n == 0 || !(r_max > 0)) return;
  grids_.resize(1);
  grids_[0].build(x, ids_[0], 2.0 * r_max);

  NeighbourList rows;
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
  out.reserve(rows.pairs());
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t k = rows.offset[i]; k < rows.offset[i + 1]; ++k)
      out.emplace_back(static_cast<int>(i), rows.index[k]);
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
