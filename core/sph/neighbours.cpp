// SPDX-License-Identifier: MIT
#include "core/sph/neighbours.hpp"

#include "core/common/heap_bytes.hpp"
#include "core/common/omp_threads.hpp"

#include <algorithm>
#include <cmath>

namespace fesph {

namespace {

// Up to this share of the particles past their Verlet margin are re-seated (paired again
// through a grid); more, and the list is built afresh, which costs about as much.
constexpr std::size_t kReseatShare = 8;  // 1 in 8
// Displacements per group whose median is taken as the Verlet lists' common translation.
constexpr std::size_t kShiftSamples = 256;

// Blocks of rows per thread in buildRows, handed out as threads come free: a thread slowed by
// another tenant (or given the dearer rows) no longer holds the other at the end.
constexpr std::size_t kBlocksPerThread = 4;

/// Compressed rows built in parallel without atomics: the rows are cut into contiguous blocks
/// (kBlocksPerThread per thread), each collected into its own buffer by whichever thread takes
/// it, and each buffer is copied to its place once the row lengths are known. The result is
/// the same for any number of threads.
/// collect(i, buf) appends row i (already in its final order) to buf. `work`, if given
/// (size n + 1, non-decreasing from 0), is the work before each row: the blocks then take
/// equal shares of it instead of equal numbers of rows (rows of unequal cost: a thread
/// with the cheap ones waited for the other through half of the Verlet filter).
template <class Collect>
void buildRows(std::size_t n, Collect&& collect, std::vector<ThreadBuffer<std::vector<int>>>& block_buf,
               std::vector<std::size_t>& count, NeighbourList& out,
               const std::vector<std::size_t>* work = nullptr) {
  const std::size_t blocks = kBlocksPerThread * static_cast<std::size_t>(maxThreads());
  block_buf.resize(blocks);
  count.assign(n, 0);
  out.offset.assign(n + 1, 0);
  // First row of block b: the first row with at least its share of the work before it.
  const auto blockStart = [&](std::size_t b) -> std::size_t {
    if (!work || b == 0 || b == blocks) return n * b / blocks;
    const std::size_t share = (*work)[n] / blocks * b + (*work)[n] % blocks * b / blocks;
    return static_cast<std::size_t>(std::lower_bound(work->begin(), work->begin() +
                                                     static_cast<std::ptrdiff_t>(n), share) -
                                    work->begin());
  };
  const long nb = static_cast<long>(blocks);
#pragma omp parallel
  {
#pragma omp for schedule(dynamic, 1)
    for (long b = 0; b < nb; ++b) {
      std::vector<int>& buf = block_buf[static_cast<std::size_t>(b)].items;
      buf.clear();
      const std::size_t end = blockStart(static_cast<std::size_t>(b) + 1);
      for (std::size_t i = blockStart(static_cast<std::size_t>(b)); i < end; ++i) {
        const std::size_t before = buf.size();
        collect(i, buf);
        count[i] = buf.size() - before;
      }
    }
#pragma omp single
    {
      for (std::size_t i = 0; i < n; ++i) out.offset[i + 1] = out.offset[i] + count[i];
      resizeSnug(out.index, out.offset[n]);
    }
#pragma omp for schedule(dynamic, 1)
    for (long b = 0; b < nb; ++b) {
      const std::vector<int>& buf = block_buf[static_cast<std::size_t>(b)].items;
      std::copy(buf.begin(), buf.end(),
                out.index.begin() +
                    static_cast<std::ptrdiff_t>(out.offset[blockStart(static_cast<std::size_t>(b))]));
    }
  }
}

/// The candidates j of each row i that pass |x_i - x_j| < r_i + r_j: term for term the test of
/// the fresh searches (r = h for SPH pairs, the contact radii for contact pairs), so a Verlet
/// list filtered here gives their lists bit for bit.
void filterCandidates(const std::vector<Vec3>& x, const std::vector<double>& r,
                      const NeighbourList& cand, std::vector<ThreadBuffer<std::vector<int>>>& block_buf,
                      std::vector<std::size_t>& count, NeighbourList& out) {
  buildRows(
      x.size(),
      [&](std::size_t i, std::vector<int>& buf) {
        // Every candidate is written and the end moves on past those that pass: whether one
        // passes is a coin toss to the branch predictor (a third of the skin's candidates fail).
        const std::size_t begin = cand.offset[i], end = cand.offset[i + 1];
        std::size_t kept = buf.size();
        buf.resize(kept + (end - begin));
        for (std::size_t k = begin; k < end; ++k) {
          const int j = cand.index[k];
          const double reach = r[i] + r[j];
          buf[kept] = j;
          kept += (x[i] - x[j]).squaredNorm() < reach * reach ? 1 : 0;
        }
        buf.resize(kept);
      },
      block_buf, count, out, &cand.offset);
}

/// The translation u of each group (each body, or everyone: !per_body) of the particles built
/// at x_built since the build. The motion is measured relative to it: a pair's distance
/// changes by at most |d_i - u| + |d_j - u| for any common u, so a body's particles flying on
/// together force fewer builds (115 -> 86 over 344 steps late in the four-plate quick run).
/// u is the median displacement, component by component: a few particles flying off fast
/// (debris) do not move it, as they moved the centre of the box. Any u keeps the lists exact
/// (only the cost depends on it), so the median of every stride-th particle, some
/// kShiftSamples of a group, does: the whole group's medians took two thirds of the lists'
/// upkeep. `comp` is scratch.
std::vector<Vec3> groupShifts(const std::vector<Vec3>& x, const std::vector<Vec3>& x_built,
                              const std::vector<int>& body, bool per_body,
                              std::vector<std::vector<double>>& comp) {
  const std::size_t n_built = x_built.size();
  const auto groupOf = [&](std::size_t i) {
    return per_body ? static_cast<std::size_t>(body[i]) : std::size_t{0};
  };
  std::size_t n_groups = 1;
  if (per_body)
    for (std::size_t i = 0; i < n_built; ++i) n_groups = std::max(n_groups, groupOf(i) + 1);
  std::vector<std::size_t> members(n_groups, 0);
  for (std::size_t i = 0; i < n_built; ++i) ++members[groupOf(i)];
  // Every stride-th member of its group, counted down (a division per particle cost more
  // than the medians).
  std::vector<std::size_t> stride(n_groups), until_next(n_groups, 0);
  for (std::size_t g = 0; g < n_groups; ++g)
    stride[g] = std::max<std::size_t>(1, members[g] / kShiftSamples);
  comp.resize(3 * n_groups);
  for (auto& v : comp) v.clear();
  for (std::size_t i = 0; i < n_built; ++i) {
    const std::size_t g = groupOf(i);
    if (until_next[g] > 0) {
      --until_next[g];
      continue;
    }
    until_next[g] = stride[g] - 1;
    for (int a = 0; a < 3; ++a) comp[3 * g + a].push_back(x[i][a] - x_built[i][a]);
  }
  std::vector<Vec3> shift(n_groups, Vec3::Zero());
  for (std::size_t g = 0; g < n_groups; ++g)
    for (int a = 0; a < 3; ++a) {
      std::vector<double>& v = comp[3 * g + static_cast<std::size_t>(a)];
      if (v.empty()) continue;
      std::nth_element(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(v.size() / 2), v.end());
      shift[g][a] = v[v.size() / 2];
    }
  return shift;
}

/// Whether a particle built at x_built with range r_built has moved, relative to the
/// translation u, plus grown by more than its margin skin/2 r_built since (0.99 of it leaves
/// room for round-off in this test): then a pair inside its range now may not have been inside
/// the widened one at the build (triangle inequality).
bool pastMargin(const Vec3& x, const Vec3& x_built, const Vec3& u, double r, double r_built,
                double skin) {
  const double drift = (x - x_built - u).norm() + std::max(0.0, r - r_built);
  return !(drift <= 0.99 * 0.5 * skin * r_built);
}

/// Whether p lies within `reach` of every plane of `image`.
bool nearPlanes(const Reflection& image, const Vec3& p, double reach) {
  for (int a = 0; a < 3; ++a)
    if (image.flip[a] && !(std::abs(2.0 * p[a] - image.twice_position[a]) < 2.0 * reach))
      return false;
  return true;
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
  // Each bucket once (cells may share one): a bit per bucket's low six bits says which may
  // be a repeat, and only those are looked for among the listed ones (a sort of the 27 took
  // 1.5 % of a late quick run's instructions).
  std::uint64_t seen = 0;
  int n = 0;
  for (std::int64_t dz = -1; dz <= 1; ++dz)
    for (std::int64_t dy = -1; dy <= 1; ++dy)
      for (std::int64_t dx = -1; dx <= 1; ++dx) {
        const std::uint64_t b = bucketOf(ix + dx, iy + dy, iz + dz);
        const std::uint64_t bit = std::uint64_t{1} << (b & 63);
        if ((seen & bit) && std::find(out, out + n, b) != out + n) continue;
        seen |= bit;
        out[n++] = b;
      }
  return n;
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
        grids_[body[i]].appendCandidates(xi, buf, [&](int j) {
          const double support = hi + h[j];  // 2 h_ij
          return (j != static_cast<int>(i)) & ((xi - x[j]).squaredNorm() < support * support);
        });
        std::sort(buf.begin() + static_cast<std::ptrdiff_t>(first), buf.end());
      },
      block_rows_, count_, out);
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
  // Pairs added since the build (births, re-seats) are kept with the stale ones: once they
  // make a third of the list, a build sheds the stale pairs the filter keeps testing.
  bool rebuild = !(skin > 0) || (n != n_built && !appended) || (n == n_built && body != body_built) ||
                 3 * pairs_added > candidates.index.size();
  std::vector<Vec3> shift;  // the translation u of each group since the build (groupShifts)
  const auto groupOf = [&](std::size_t i) {
    return per_body ? static_cast<std::size_t>(body[i]) : std::size_t{0};
  };
  if (!rebuild) {
    shift = groupShifts(x, x_built, body, per_body, comp);
    const auto shiftOf = [&](std::size_t i) -> const Vec3& { return shift[groupOf(i)]; };
    const long nb = static_cast<long>(n_built);
    long past = 0;
    is_past.resize(n_built);
#pragma omp parallel for schedule(static) reduction(+ : past)
    for (long i = 0; i < nb; ++i) {
      is_past[i] = pastMargin(x[i], x_built[i], shiftOf(i), r[i], r_built[i], skin);
      past += is_past[i];
    }
    // A few particles past their margin (late in a run: debris flying off fast, which would
    // force a build every few steps) are re-seated: built again where they would be had they
    // moved with the shift u, so their drift starts from zero, and paired afresh
    // (pairAgain). The triangle inequality holds whatever position each particle was
    // built at, as for appended particles.
    reseated.clear();
    if (static_cast<std::size_t>(past) * kReseatShare > n_built) {
      rebuild = true;
    } else if (past > 0) {
      for (std::size_t i = 0; i < n_built; ++i) {
        if (!is_past[i]) continue;
        reseated.push_back(static_cast<int>(i));
        x_built[i] = x[i] - shiftOf(i);
        r_built[i] = r[i];
        r_wide[i] = (1.0 + 0.5 * skin) * r[i];
      }
      reseats += past;
    }
  }
  if (rebuild) {
    reseated.clear();
    pairs_added = 0;
    r_wide.resize(n);
    for (std::size_t i = 0; i < n; ++i) r_wide[i] = (1.0 + 0.5 * std::max(skin, 0.0)) * r[i];
    x_built = x;
    r_built = r;
    body_built = body;
    ++builds;
    return true;
  }
  if (appended) {
    // Built where they would be had they moved with their group's u since the build, as
    // re-seated particles are, so that their drift starts from zero: built where they are, a
    // new particle of a body flying on together was paired with the others' built positions
    // off by u, and pairs went missing (2-6 a step early in the quick four-plate run).
    for (std::size_t i = n_built; i < n; ++i)
      x_built.push_back(groupOf(i) < shift.size() ? Vec3(x[i] - shift[groupOf(i)]) : x[i]);
    r_built.insert(r_built.end(), r.begin() + static_cast<std::ptrdiff_t>(n_built), r.end());
    r_wide.resize(n);
    for (std::size_t i = n_built; i < n; ++i) r_wide[i] = (1.0 + 0.5 * skin) * r[i];
    body_built = body;
  }
  return false;
}

void NeighbourSearch::pairAgain(Verlet& v, const std::vector<int>& again, bool cross) {
  // The triangle inequality holds whatever position each particle was built at, so a particle
  // built again (appended, or re-seated) is paired at its new built position with the others
  // at theirs: the candidates are then the pairs a fresh build would give if each particle had
  // stayed where it was built, and every later drift check measures from there. The pairs it
  // had stay (a superset is harmless: the filter decides); only the missing ones are added.
  const std::size_t n = v.x_built.size();
  const std::vector<int>& body = v.body_built;
  NeighbourList& c = v.candidates;
  if (c.offset.empty()) c.offset.assign(1, 0);
  // The rows list only partners below their own count: a pair with a particle appended since
  // cannot be listed yet, so only pairs of two older particles are looked up below.
  const int n_listed = static_cast<int>(c.offset.size() - 1);
  c.offset.resize(n + 1, c.offset.back());  // appended particles: empty rows

  // One grid of the built positions: per body that has such particles, or one over all (cross).
  int n_grids = 1;
  if (!cross)
    for (int b : body) n_grids = std::max(n_grids, b + 1);
  const auto grid_of = [&](std::size_t i) { return cross ? 0 : body[i]; };
  std::vector<char> in_again(n, 0), needed(static_cast<std::size_t>(n_grids), 0);
  for (int i : again) {
    in_again[static_cast<std::size_t>(i)] = 1;
    needed[grid_of(static_cast<std::size_t>(i))] = 1;
  }
  ids_.resize(static_cast<std::size_t>(n_grids));
  for (auto& ids : ids_) ids.clear();
  std::vector<double> r_max(static_cast<std::size_t>(n_grids), 0.0);
  for (std::size_t i = 0; i < n; ++i)
    if (needed[grid_of(i)]) {
      ids_[grid_of(i)].push_back(static_cast<int>(i));
      r_max[grid_of(i)] = std::max(r_max[grid_of(i)], v.r_wide[i]);
    }
  grids_.resize(static_cast<std::size_t>(n_grids));
  for (int g = 0; g < n_grids; ++g)
    if (needed[g]) grids_[g].build(v.x_built, ids_[g], 2.0 * r_max[g]);

  // The fresh search's test on the built positions. A pair goes to the rows of both partners
  // (same body) or of the lower one (cross); a pair of two such particles is found once. Only
  // the pairs the rows lack are kept, looked up here in parallel (the rows do not change until
  // the merge below).
  const auto lacks = [&](int row, int partner) {
    if (row >= n_listed || partner >= n_listed) return true;
    const auto first = c.index.begin() + static_cast<std::ptrdiff_t>(c.offset[row]);
    const auto last = c.index.begin() + static_cast<std::ptrdiff_t>(c.offset[row + 1]);
    return !std::binary_search(first, last, partner);
  };
  const long na = static_cast<long>(again.size());
  std::vector<std::vector<std::pair<int, int>>> found(again.size());  // (row, partner)
#pragma omp parallel for schedule(dynamic, 16) if (na > 64)
  for (long k = 0; k < na; ++k) {
    const int i = again[static_cast<std::size_t>(k)];
    const Vec3 xi = v.x_built[static_cast<std::size_t>(i)];
    const double ri = v.r_wide[static_cast<std::size_t>(i)];
    const int bi = body[static_cast<std::size_t>(i)];
    thread_local std::vector<int> near;  // the pairs of i, in the grid's order
    near.clear();
    grids_[grid_of(static_cast<std::size_t>(i))].appendCandidates(xi, near, [&](int j) {
      const std::size_t js = static_cast<std::size_t>(j);
      const double reach = ri + v.r_wide[js];
      return (j != i) & ((body[js] != bi) == cross) &
             !(in_again[js] & (j < i)) &  // two paired again: found by the lower one's search
             ((xi - v.x_built[js]).squaredNorm() < reach * reach);
    });
    for (const int j : near) {
      if (cross) {
        const int lo = std::min(i, j), hi = std::max(i, j);
        if (lacks(lo, hi)) found[k].emplace_back(lo, hi);
      } else if (lacks(i, j)) {
        // Same-body rows are symmetric (j in i's row exactly when i is in j's: a build's test
        // is, and every pair is added to both rows), so i's row, in cache, answers for j's,
        // whose look-up missed the cache (a third of this search in an impact).
        found[k].emplace_back(i, j);
        found[k].emplace_back(j, i);
      }
    }
  }

  v.pairs_added += v.addPairs(found);
}

std::size_t NeighbourSearch::Verlet::addPairs(
    const std::vector<std::vector<std::pair<int, int>>>& found) {
  // The additions by row (a counting sort), then each row merged with its own, ascending as a
  // fresh build gives them; the rows in parallel, each alone.
  NeighbourList& c = candidates;
  const std::size_t n = c.offset.size() - 1;
  add_offset.assign(n + 1, 0);
  for (const auto& f : found)
    for (const auto& e : f) ++add_offset[static_cast<std::size_t>(e.first) + 1];
  for (std::size_t i = 0; i < n; ++i) add_offset[i + 1] += add_offset[i];
  if (add_offset[n] == 0) return 0;
  add.resize(add_offset[n]);
  {
    std::vector<std::size_t> fill(add_offset.begin(), add_offset.end() - 1);
    for (const auto& f : found)
      for (const auto& [row, partner] : f) add[fill[static_cast<std::size_t>(row)]++] = partner;
  }
  std::vector<std::size_t>& offset = merged.offset;
  std::vector<int>& index = merged.index;
  offset.resize(n + 1);
  for (std::size_t i = 0; i <= n; ++i) offset[i] = c.offset[i] + add_offset[i];
  resizeSnug(index, offset[n]);
  const long rows = static_cast<long>(n);
#pragma omp parallel for schedule(static)
  for (long r = 0; r < rows; ++r) {
    const std::size_t i = static_cast<std::size_t>(r);
    const auto add_first = add.begin() + static_cast<std::ptrdiff_t>(add_offset[i]);
    const auto add_last = add.begin() + static_cast<std::ptrdiff_t>(add_offset[i + 1]);
    std::sort(add_first, add_last);
    std::merge(c.index.begin() + static_cast<std::ptrdiff_t>(c.offset[i]),
               c.index.begin() + static_cast<std::ptrdiff_t>(c.offset[i + 1]), add_first, add_last,
               index.begin() + static_cast<std::ptrdiff_t>(offset[i]));
  }
  c.offset.swap(offset);
  c.index.swap(index);
  return add_offset[n];
}

/// Rows of the candidates for the particles appended since the last update and the ones
/// re-seated by it.
void NeighbourSearch::pairAgain(Verlet& v, std::size_t n_old, bool cross) {
  std::vector<int> again = v.reseated;
  for (std::size_t i = n_old; i < v.x_built.size(); ++i) again.push_back(static_cast<int>(i));
  if (!again.empty()) pairAgain(v, again, cross);
}

void NeighbourSearch::sphNeighboursVerlet(const std::vector<Vec3>& x, const std::vector<double>& h,
                                          const std::vector<int>& body, double skin,
                                          NeighbourList& out) {
  const std::size_t n_old = sph_.x_built.size();
  if (sph_.update(x, h, body, skin, true))
    sphNeighbours(x, sph_.r_wide, body, sph_.candidates);
  else
    pairAgain(sph_, n_old, false);
  filterCandidates(x, h, sph_.candidates, block_rows_, count_, out);
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
        grids_[0].appendCandidates(x[i], buf, [&](int j) {
          const double reach = r[i] + r[j];
          return (j > static_cast<int>(i)) & (body[j] != body[i]) &
                 ((x[i] - x[j]).squaredNorm() < reach * reach);
        });
        std::sort(buf.begin() + static_cast<std::ptrdiff_t>(first), buf.end());
      },
      block_rows_, count_, rows);
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
  const std::size_t n_old = contact_.x_built.size();
  if (contact_.update(x, r, body, skin, false))
    crossBodyRows(x, contact_.r_wide, body, contact_.candidates);
  else
    pairAgain(contact_, n_old, true);
  filterCandidates(x, r, contact_.candidates, block_rows_, count_, rows_);
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
  const auto near_planes = [&](std::size_t i) { return nearPlanes(image, x[i], 2.0 * r_max); };
  mirror_ids_.clear();
  mirror_work_.assign(n + 1, 0);  // the rows near the planes before each row: their work
  for (std::size_t i = 0; i < n; ++i) {
    if (near_planes(i)) mirror_ids_.push_back(static_cast<int>(i));
    mirror_work_[i + 1] = mirror_ids_.size();
  }
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
        mirror_grid_.appendCandidates(image.point(x[i]), buf, [&](int j) {
          const bool take = same_body ? body[j] == body[i]
                                      : (body[j] != body[i]) & (j > static_cast<int>(i));
          const double reach = r[i] + r[j];
          return take & ((x[i] - image.point(x[j])).squaredNorm() < reach * reach);
        });
        std::sort(buf.begin() + static_cast<std::ptrdiff_t>(first), buf.end());
      },
      block_rows_, count_, out, &mirror_work_);
}

void NeighbourSearch::mirrorRowsVerlet(const std::vector<Vec3>& x, const std::vector<double>& r,
                                       const std::vector<int>& body, const Reflection& image,
                                       bool same_body, std::size_t which, double skin,
                                       NeighbourList& out) {
  const std::size_t slot = 2 * which + (same_body ? 0 : 1);
  if (mirror_verlet_.size() <= slot) mirror_verlet_.resize(slot + 1);
  MirrorVerlet& m = mirror_verlet_[slot];
  Verlet& v = m.lists;
  const std::size_t n = x.size(), n_built = v.x_built.size();
  double r_max = 0;
  for (double ri : r) r_max = std::max(r_max, ri);
  // mirrorRows' own test of the points it searches (within 2 max(r) of every plane)
  const auto searched = [&](const Vec3& p) { return nearPlanes(image, p, 2.0 * r_max); };
  // Every built point on the same side of every plane of the image: then a pair within
  // r_i + r_j of the image is within that of every plane (|x_i - M x_j| >= |d_i + d_j| =
  // |d_i| + |d_j| on a flipped axis), so mirrorRows' search finds all of them.
  const auto sameSide = [&](const Vec3& p) {
    for (int a = 0; a < 3; ++a) {
      if (!image.flip[a]) continue;
      const double d = 2.0 * p[a] - image.twice_position[a];
      if (d != 0 && (d > 0) != m.positive[a]) return false;
    }
    return true;
  };
  bool same_image = true;
  for (int a = 0; a < 3; ++a)
    same_image = same_image && image.flip[a] == m.image.flip[a] &&
                 (!image.flip[a] || image.twice_position[a] == m.image.twice_position[a]);
  bool rebuild = !(skin > 0) || !m.one_side || n_built == 0 || n < n_built || !same_image ||
                 !std::equal(v.body_built.begin(), v.body_built.end(), body.begin());
  if (!rebuild) {
    // A pair of points near the planes now (the only ones mirrorRows pairs) was a candidate
    // as long as neither moved, relative to the translation of its body (same body) or of
    // all (pairs across bodies), plus grew by more than its margin skin/2 r_built (triangle
    // inequality, M being an isometry). The translation keeps no component across a plane:
    // M u = u, so it leaves |x_i - M x_j| unchanged.
    std::vector<Vec3> shift = groupShifts(x, v.x_built, body, same_body, v.comp);
    const auto groupOf = [&](std::size_t i) {
      return same_body ? static_cast<std::size_t>(body[i]) : std::size_t{0};
    };
    for (Vec3& u : shift)
      for (int a = 0; a < 3; ++a)
        if (image.flip[a]) u[a] = 0;
    long past = 0;
    const long nb = static_cast<long>(n_built);
#pragma omp parallel for schedule(static) reduction(+ : past)
    for (long k = 0; k < nb; ++k) {
      const std::size_t i = static_cast<std::size_t>(k);
      if (!searched(x[i])) continue;
      past += pastMargin(x[i], v.x_built[i], shift[groupOf(i)], r[i], v.r_built[i], skin);
    }
    rebuild = past > 0;
    // Points appended since the build (conversions), on the side of the others and no wider
    // than the widest, are built where they would be had they moved with their body, and
    // paired there with the built points near the planes (`band`: the only ones a pair at
    // the widened ranges can hold), as a build would pair them.
    for (std::size_t i = n_built; i < n && !rebuild; ++i)
      rebuild = (1.0 + 0.5 * skin) * r[i] > m.r_wide_max || !sameSide(x[i]);
    if (!rebuild && n > n_built) {
      std::vector<std::pair<int, int>>& added = m.added.front();  // (row, partner)
      added.clear();
      for (std::size_t i = n_built; i < n; ++i) {
        const std::size_t g = groupOf(i);
        v.x_built.push_back(g < shift.size() ? Vec3(x[i] - shift[g]) : x[i]);
        v.r_built.push_back(r[i]);
        v.r_wide.push_back((1.0 + 0.5 * skin) * r[i]);
        const Vec3& xi = v.x_built[i];
        if (!nearPlanes(image, xi, 2.0 * m.r_wide_max)) continue;
        const int ii = static_cast<int>(i);
        for (int j : m.band) {
          const bool take = same_body ? body[j] == body[i] : body[j] != body[i];
          const double reach = v.r_wide[i] + v.r_wide[static_cast<std::size_t>(j)];
          if (!take || !((xi - image.point(v.x_built[j])).squaredNorm() < reach * reach)) continue;
          added.emplace_back(j, ii);                  // j < i: at the end of j's row
          if (same_body) added.emplace_back(ii, j);  // i's own row, ascending
        }
        const double reach = 2.0 * v.r_wide[i];
        if (same_body && (xi - image.point(xi)).squaredNorm() < reach * reach)
          added.emplace_back(ii, ii);  // i with its own image
        m.band.push_back(ii);
      }
      v.body_built = body;
      v.candidates.offset.resize(n + 1, v.candidates.offset.back());  // rows of the new points
      v.addPairs(m.added);
    }
  }
  if (rebuild) {
    m.image = image;
    v.x_built = x;
    v.r_built = r;
    v.body_built = body;
    v.r_wide.resize(n);
    m.r_wide_max = 0;
    for (std::size_t i = 0; i < n; ++i) {
      v.r_wide[i] = (1.0 + 0.5 * std::max(skin, 0.0)) * r[i];
      m.r_wide_max = std::max(m.r_wide_max, v.r_wide[i]);
    }
    for (int a = 0; a < 3; ++a) {  // the side of the first point off each plane
      m.positive[a] = true;
      for (std::size_t i = 0; i < n && image.flip[a]; ++i) {
        const double d = 2.0 * x[i][a] - image.twice_position[a];
        if (d != 0) {
          m.positive[a] = d > 0;
          break;
        }
      }
    }
    m.one_side = true;
    for (std::size_t i = 0; i < n && m.one_side; ++i) m.one_side = sameSide(x[i]);
    m.band.clear();
    for (std::size_t i = 0; i < n; ++i)
      if (nearPlanes(image, x[i], 2.0 * m.r_wide_max)) m.band.push_back(static_cast<int>(i));
    mirrorRows(x, v.r_wide, body, image, same_body, v.candidates);
    ++v.builds;
  }
  // mirrorRows' rows from the candidates (of the bodies it pairs): its test, on points it
  // searches.
  buildRows(
      n,
      [&](std::size_t i, std::vector<int>& buf) {
        if (!searched(x[i])) return;
        for (std::size_t k = v.candidates.offset[i]; k < v.candidates.offset[i + 1]; ++k) {
          const int j = v.candidates.index[k];
          const double reach = r[i] + r[j];
          if (searched(x[j]) &&
              (x[i] - image.point(x[j])).squaredNorm() < reach * reach)
            buf.push_back(j);
        }
      },
      block_rows_, count_, out, &v.candidates.offset);
}

std::size_t CellGrid::bytes() const { return heapBytes(start_, sorted_); }

std::size_t NeighbourSearch::Verlet::bytes() const {
  return heapBytes(candidates.offset, candidates.index, x_built, r_built, r_wide, body_built) +
         heapBytes(reseated, merged.offset, merged.index, add_offset, add, comp, is_past);
}

std::size_t NeighbourSearch::MirrorVerlet::bytes() const {
  return lists.bytes() + heapBytes(band) + heapBytes(added);
}

std::size_t NeighbourSearch::bytes() const {
  std::size_t b = sph_.bytes() + contact_.bytes() + mirror_grid_.bytes() +
                  heapBytes(mirror_ids_, mirror_work_, ids_, block_rows_, count_) +
                  heapBytes(rows_.offset, rows_.index);
  for (const CellGrid& g : grids_) b += g.bytes();
  for (const MirrorVerlet& m : mirror_verlet_) b += m.bytes();
  return b;
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
