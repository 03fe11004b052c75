// SPDX-License-Identifier: MIT
#include "core/contact/broad_phase.hpp"

#include "core/common/omp_threads.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace fesph {

namespace {

/// Cell coordinates of the uniform grid, hashed into a power-of-two bucket table.
struct Grid {
  Vec3 origin = Vec3::Zero();
  double inv_h = 0;
  std::array<long, 3> max_cell = {0, 0, 0};  ///< cells beyond the faces' bounds hold nothing
  std::uint64_t mask = 0;

  long cell(double p, int d) const {
    const long c = static_cast<long>(std::floor((p - origin[d]) * inv_h));
    return std::clamp(c, 0L, max_cell[d]);
  }
  static std::uint64_t hash(long i, long j, long k) {
    return static_cast<std::uint64_t>(i) * 73856093u ^ static_cast<std::uint64_t>(j) * 19349663u ^
           static_cast<std::uint64_t>(k) * 83492791u;
  }
  std::size_t bucket(std::uint64_t h) const { return static_cast<std::size_t>(h & mask); }
  /// f(hash) for every cell the box [lo, hi] touches.
  template <class F>
  void forEachCell(const Vec3& lo, const Vec3& hi, F&& f) const {
    for (long k = cell(lo.z(), 2); k <= cell(hi.z(), 2); ++k)
      for (long j = cell(lo.y(), 1); j <= cell(hi.y(), 1); ++j)
        for (long i = cell(lo.x(), 0); i <= cell(hi.x(), 0); ++i) f(hash(i, j, k));
  }
};

bool overlaps(const Vec3& alo, const Vec3& ahi, const Vec3& blo, const Vec3& bhi) {
  return (alo.array() <= bhi.array()).all() && (blo.array() <= ahi.array()).all();
}

/// Per body, the bounds of a set of boxes (empty: +inf / -inf).
struct BodyBounds {
  std::vector<Vec3> lo, hi;
  explicit BodyBounds(std::size_t nbodies)
      : lo(nbodies, Vec3::Constant(std::numeric_limits<double>::infinity())),
        hi(nbodies, Vec3::Constant(-std::numeric_limits<double>::infinity())) {}
  void add(std::size_t body, const Vec3& box_lo, const Vec3& box_hi) {
    lo[body] = lo[body].cwiseMin(box_lo);
    hi[body] = hi[body].cwiseMax(box_hi);
  }
  void add(const BodyBounds& other) {
    for (std::size_t b = 0; b < lo.size(); ++b) add(b, other.lo[b], other.hi[b]);
  }
  /// Whether the box [box_lo, box_hi] of body `own` meets the bounds of another body.
  bool meetsOther(std::size_t own, const Vec3& box_lo, const Vec3& box_hi) const {
    for (std::size_t b = 0; b < lo.size(); ++b)
      if (b != own && overlaps(box_lo, box_hi, lo[b], hi[b])) return true;
    return false;
  }
};

}  // namespace

void findContactCandidates(Model& model, double dt, double depth_tolerance) {
  const Nodes& nd = model.nodes;
  Surfaces& s = model.surfaces;
  ContactScratch& w = s.scratch;
  ContactCandidates& out = s.candidates;
  const std::size_t nfaces = s.exterior.size();

  // Slaves in body order.
  out.slaves.clear();
  out.body_begin.assign(1, 0);
  for (const std::vector<int>& list : s.slave_nodes) {
    for (int a : list)
      if (nd.m[a] > 0) out.slaves.push_back(a);
    out.body_begin.push_back(out.slaves.size());
  }
  const std::size_t nslaves = out.slaves.size();
  const std::size_t nbodies = out.body_begin.size() - 1;
  out.offset.assign(nslaves + 1, 0);
  out.faces.clear();
  out.active.clear();
  if (nfaces == 0 || nslaves == 0) return;

  // Swept, widened face boxes and each body's bounds of them; the cell size is their mean
  // largest extent. (Bounds by min and max: the same for any thread count.)
  w.face_lo.resize(nfaces);
  w.face_hi.resize(nfaces);
  w.face_tol.resize(nfaces);
  double extent_sum = 0;
  BodyBounds face_bounds(nbodies);
#pragma omp parallel if (nfaces > 256)
  {
    BodyBounds mine(nbodies);
#pragma omp for schedule(static) reduction(+ : extent_sum)
    for (std::size_t f = 0; f < nfaces; ++f) {
      const auto& n = s.exterior[f].node;
      Vec3 lo = nd.x[n[0]], hi = nd.x[n[0]];
      for (int i = 0; i < 3; ++i) {
        const Vec3& x = nd.x[n[i]];
        const Vec3 y = x + dt * nd.v[n[i]];
        lo = lo.cwiseMin(x).cwiseMin(y);
        hi = hi.cwiseMax(x).cwiseMax(y);
      }
      const double tol = depth_tolerance * std::sqrt(longestEdgeSquared(nd.x, s.exterior[f]));
      w.face_tol[f] = tol;
      w.face_lo[f] = lo.array() - tol;
      w.face_hi[f] = hi.array() + tol;
      extent_sum += (w.face_hi[f] - w.face_lo[f]).maxCoeff();
      mine.add(static_cast<std::size_t>(s.exterior[f].body), w.face_lo[f], w.face_hi[f]);
    }
#pragma omp critical
    face_bounds.add(mine);
  }

  // The slaves' segments over the step, each body's bounds of them, and the slaves whose
  // segment meets another body's faces' bounds (ascending: each thread lists a contiguous
  // share, joined in thread order). Only those query the grid, and only the faces whose box
  // meets another body's slaves' bounds enter it: the box tests decide the candidates, so
  // they are the same, and most faces of spaced plates, far from every other body, stay out.
  w.slave_lo.resize(nslaves);
  w.slave_hi.resize(nslaves);
  const int nthreads = maxThreads();
  w.thread_faces.resize(nthreads);
  for (auto& list : w.thread_faces) list.items.clear();
  BodyBounds slave_bounds(nbodies);
#pragma omp parallel if (nslaves > 256)
  {
    BodyBounds mine(nbodies);
    std::vector<int>& queried = w.thread_faces[threadId()].items;
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < nslaves; ++i) {
      const int a = out.slaves[i];
      const Vec3 y = nd.x[a] + dt * nd.v[a];
      w.slave_lo[i] = nd.x[a].cwiseMin(y);
      w.slave_hi[i] = nd.x[a].cwiseMax(y);
      const std::size_t body = static_cast<std::size_t>(nd.body[a]);
      mine.add(body, w.slave_lo[i], w.slave_hi[i]);
      if (face_bounds.meetsOther(body, w.slave_lo[i], w.slave_hi[i]))
        queried.push_back(static_cast<int>(i));
    }
#pragma omp critical
    slave_bounds.add(mine);
  }
  w.queried.clear();
  for (const auto& list : w.thread_faces)
    w.queried.insert(w.queried.end(), list.items.begin(), list.items.end());
  if (w.queried.empty()) return;

  Vec3 all_lo = face_bounds.lo[0], all_hi = face_bounds.hi[0];
  for (std::size_t b = 1; b < nbodies; ++b) {
    all_lo = all_lo.cwiseMin(face_bounds.lo[b]);
    all_hi = all_hi.cwiseMax(face_bounds.hi[b]);
  }
  Grid grid;
  const double h = extent_sum / static_cast<double>(nfaces);
  grid.origin = all_lo;
  grid.inv_h = 1.0 / h;
  for (int d = 0; d < 3; ++d)
    grid.max_cell[d] = static_cast<long>(std::floor((all_hi[d] - all_lo[d]) * grid.inv_h));

  // Faces into buckets: each thread lists the (cell hash, face) pairs of a contiguous range of
  // faces, then a counting sort by bucket keeps the faces of each bucket ascending (the same
  // table for any thread count).
  w.thread_cells.resize(nthreads);
  // All cleared here: a team of one (few faces) leaves the other lists as an earlier call
  // filled them, and they are all read below.
  for (auto& list : w.thread_cells) list.items.clear();
#pragma omp parallel if (nfaces > 256)
  {
    std::vector<std::pair<std::uint64_t, int>>& mine = w.thread_cells[threadId()].items;
#pragma omp for schedule(static)
    for (std::size_t f = 0; f < nfaces; ++f)
      if (slave_bounds.meetsOther(static_cast<std::size_t>(s.exterior[f].body), w.face_lo[f],
                                  w.face_hi[f]))
        grid.forEachCell(w.face_lo[f], w.face_hi[f],
                         [&](std::uint64_t h) { mine.emplace_back(h, static_cast<int>(f)); });
  }
  std::size_t inserts = 0;
  for (int t = 0; t < nthreads; ++t) inserts += w.thread_cells[t].items.size();
  // About two entries per bucket: a collision only adds faces that the box test rejects, and
  // a sparser table cost more to clear and sum every step than the collisions (BM_ImpactStep
  // at 197k tets, 2 threads: 176 ns with 2 buckets per entry, 161 ns with 1/2).
  std::size_t nbuckets = 1;
  while (2 * nbuckets < inserts) nbuckets *= 2;
  grid.mask = nbuckets - 1;
  w.bucket_offset.assign(nbuckets + 1, 0);
  for (int t = 0; t < nthreads; ++t)
    for (const auto& [h, f] : w.thread_cells[t].items) ++w.bucket_offset[grid.bucket(h) + 1];
  for (std::size_t b = 0; b < nbuckets; ++b) w.bucket_offset[b + 1] += w.bucket_offset[b];
  w.bucket_faces.resize(inserts);
  w.bucket_fill.assign(w.bucket_offset.begin(), w.bucket_offset.end() - 1);
  for (int t = 0; t < nthreads; ++t)
    for (const auto& [h, f] : w.thread_cells[t].items) w.bucket_faces[w.bucket_fill[grid.bucket(h)]++] = f;

  // Query the slaves in parallel into per-thread lists, then copy them out in slave order (so
  // any thread may take any slave: dynamic, as their candidate counts differ).
  for (auto& list : w.thread_faces) list.items.clear();
  const std::size_t nq = w.queried.size();
  w.slave_thread.resize(nq);
  w.slave_start.resize(nq);
#pragma omp parallel if (nq > 256)
  {
    std::vector<int>& list = w.thread_faces[threadId()].items;
#pragma omp for schedule(dynamic, 64)
    for (std::size_t q = 0; q < nq; ++q) {
      const std::size_t i = static_cast<std::size_t>(w.queried[q]);
      const int a = out.slaves[i];
      const Vec3 &lo = w.slave_lo[i], &hi = w.slave_hi[i];
      const std::size_t start = list.size();
      grid.forEachCell(lo, hi, [&](std::uint64_t h) {
        const std::size_t b = grid.bucket(h);
        for (std::size_t k = w.bucket_offset[b]; k < w.bucket_offset[b + 1]; ++k) {
          const int f = w.bucket_faces[k];
          if (s.exterior[f].body != nd.body[a] && overlaps(lo, hi, w.face_lo[f], w.face_hi[f]))
            list.push_back(f);
        }
      });
      std::sort(list.begin() + start, list.end());
      list.erase(std::unique(list.begin() + start, list.end()), list.end());
      w.slave_thread[q] = threadId();
      w.slave_start[q] = start;
      out.offset[i + 1] = list.size() - start;
    }
  }
  for (std::size_t q = 0; q < nq; ++q)
    if (out.offset[static_cast<std::size_t>(w.queried[q]) + 1] > 0)
      out.active.push_back(w.queried[q]);
  for (std::size_t i = 0; i < nslaves; ++i) out.offset[i + 1] += out.offset[i];
  out.faces.resize(out.offset[nslaves]);
#pragma omp parallel for schedule(static) if (nq > 256)
  for (std::size_t q = 0; q < nq; ++q) {
    const std::size_t i = static_cast<std::size_t>(w.queried[q]);
    const std::vector<int>& list = w.thread_faces[w.slave_thread[q]].items;
    std::copy(list.begin() + w.slave_start[q],
              list.begin() + w.slave_start[q] + (out.offset[i + 1] - out.offset[i]),
              out.faces.begin() + out.offset[i]);
  }
}

}  // namespace fesph
