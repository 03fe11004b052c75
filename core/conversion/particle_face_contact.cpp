// SPDX-License-Identifier: MIT
#include "core/conversion/particle_face_contact.hpp"

#include "core/conversion/face_geometry.hpp"
#include "core/common/heap_bytes.hpp"
#include "core/common/omp_threads.hpp"
#include "core/common/thread_buffer.hpp"
#include "core/common/union_find.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <climits>
#include <utility>
#include <vector>

namespace fesph {

namespace {

// Uniform hash grid of the exterior faces' swept boxes (start and predicted end positions,
// inflated by the largest contact radius and particle travel). A particle only needs the
// faces of the cell its predicted position falls in. The cell follows the typical face (the
// median longest edge), not the largest: a graded plate's coarse rim faces would otherwise
// make cells that hold hundreds of the fine faces where the particles are. A face larger than
// a cell is entered in every cell its box touches, so the candidates are the same faces in
// the same (ascending) order whatever the cell size.
struct FaceGrid {
  double cell = 0;
  /// The faces entered in the cells that hold a particle, by the rank of the cell's key among
  /// theirs: cell r's faces are face[start[r]] .. face[start[r + 1] - 1], ascending, each once.
  /// Keys may collide (a hash): a collision only adds candidates. Degenerate faces are left out.
  std::vector<std::size_t> start;
  std::vector<int> face;
  /// Each particle's cell rank (-1: tied, in no cell).
  std::vector<int> rank_of;
  /// Each face with entries: its plane at the start of the step (a point of it, its first
  /// node, and the unit normal) and the box a particle's predicted position must lie in for
  /// the face to be one of its candidates (buildGrid), side by side for the one look-up a
  /// face of the cell costs.
  struct Entry {
    Vec3 point, normal;
    Vec3 lo, hi;
  };
  std::vector<Entry> entry;

  // Unsigned arithmetic: the hash wraps instead of overflowing (undefined behaviour) for
  // far or non-finite positions, which the solver's non-finite check reports after the step.
  static std::int64_t key(long i, long j, long k) {
    const std::uint64_t h = (static_cast<std::uint64_t>(i) * 73856093u) ^
                            (static_cast<std::uint64_t>(j) * 19349663u) ^
                            (static_cast<std::uint64_t>(k) * 83492791u);
    return static_cast<std::int64_t>(h);
  }
  /// The index of the cell along an axis that holds coordinate c.
  long index(double c) const { return std::lround(std::floor(c / cell)); }
};

// Below this many items a loop runs on one thread: forking costs more than it saves. Low
// enough that the determinism test's few dozen particles split over the threads.
constexpr long kParallelMin = 32;

// How far outside a face (in barycentric weights) a particle's end may project and still hit
// it, so that a particle over the edge between two faces is caught by one of them.
constexpr double kBaryTolerance = 0.05;

// Contiguous blocks of n items that the threads take as they come (items of unequal work),
// results joined in block order: as many for any thread count, so the same result.
// At least 16 items a block, so that the determinism test's few dozen make several.
long blockCount(long n) { return std::clamp((n + 15) / 16, 1L, 64L); }

// The occupied cells' keys, numbered in the order they are met, in an open-addressing table
// (at most half full) with a bitmap of their low bits in front: most cells a face box touches
// hold no particle, and one bit test answers that without a probe. Sized for `most` keys.
class KeySet {
 public:
  explicit KeySet(std::size_t most) {
    std::size_t slots = 64;
    while (slots < 2 * most) slots <<= 1;
    keys_.resize(slots);
    rank_.assign(slots, -1);
    while ((std::size_t{1} << (64 - shift_)) < slots) --shift_;
    bitmap_.assign(8 * slots / 64, 0);  // 16 bits a key at most: at most 1 bit in 16 set
    mask_ = 8 * slots - 1;
  }
  /// The rank of key k, numbered now if it is new.
  int insert(std::int64_t k) {
    std::size_t i = slot(k);
    for (; rank_[i] >= 0; i = (i + 1) & (keys_.size() - 1))
      if (keys_[i] == k) return rank_[i];
    keys_[i] = k;
    rank_[i] = size_++;
    const std::uint64_t b = static_cast<std::uint64_t>(k) & mask_;
    bitmap_[b / 64] |= std::uint64_t{1} << (b % 64);
    return rank_[i];
  }
  /// The rank of key k, or -1 if it is not one of them.
  int rank(std::int64_t k) const {
    const std::uint64_t b = static_cast<std::uint64_t>(k) & mask_;
    if ((bitmap_[b / 64] >> (b % 64) & 1) == 0) return -1;
    for (std::size_t i = slot(k); rank_[i] >= 0; i = (i + 1) & (keys_.size() - 1))
      if (keys_[i] == k) return rank_[i];
    return -1;
  }
  std::size_t size() const { return static_cast<std::size_t>(size_); }

 private:
  // Fibonacci hashing: the top bits of the product spread keys whose low bits agree.
  std::size_t slot(std::int64_t k) const {
    const std::uint64_t spread = static_cast<std::uint64_t>(k) * 0x9E3779B97F4A7C15u;
    return static_cast<std::size_t>(spread >> shift_);
  }
  std::vector<std::int64_t> keys_;
  std::vector<int> rank_;  ///< -1: empty slot
  std::vector<std::uint64_t> bitmap_;
  std::uint64_t mask_ = 0;
  int shift_ = 63;
  int size_ = 0;
};

// Only the cells that hold a particle's predicted position get entries: most faces of a
// plate are far from every particle. Faces are entered in parallel; the final counting sort
// makes the entries independent of the thread count.
FaceGrid buildGrid(const Model& model, double dt, double reach) {
  const Nodes& nd = model.nodes;
  const Particles& pa = model.particles;
  const auto& faces = model.surfaces.exterior;
  const long nf = static_cast<long>(faces.size()), np = static_cast<long>(pa.size());
  FaceGrid g;
  // The median longest edge, from the squares: sqrt is monotonic and correctly rounded, so the
  // root of the median square is the median length bit for bit, for one sqrt instead of nf.
  std::vector<double> longest_sq(faces.size());
#pragma omp parallel for schedule(static) if (nf > kParallelMin)
  for (long k = 0; k < nf; ++k) longest_sq[k] = longestEdgeSquared(nd.x, faces[k]);
  std::nth_element(longest_sq.begin(), longest_sq.begin() + longest_sq.size() / 2,
                   longest_sq.end());
  g.cell = std::max(std::sqrt(longest_sq[longest_sq.size() / 2]), 2 * reach);
  std::vector<std::int64_t> cell_of(pa.size());
  std::vector<char> untied(pa.size());
  // The range of the occupied cells' indices: a face's box is searched only where it
  // overlaps it (most of a plate's faces are far from every particle, and skip at once).
  long i_min = LONG_MAX, j_min = LONG_MAX, k_min = LONG_MAX;
  long i_max = LONG_MIN, j_max = LONG_MIN, k_max = LONG_MIN;
#pragma omp parallel for schedule(static) if (np > kParallelMin) \
    reduction(min : i_min, j_min, k_min) reduction(max : i_max, j_max, k_max)
  for (long p = 0; p < np; ++p) {
    untied[p] = !pa.tie[p].active();
    if (!untied[p]) continue;
    const Vec3 y = pa.x[p] + dt * pa.v[p];
    const long i = g.index(y.x()), j = g.index(y.y()), k = g.index(y.z());
    cell_of[p] = FaceGrid::key(i, j, k);
    i_min = std::min(i_min, i), j_min = std::min(j_min, j), k_min = std::min(k_min, k);
    i_max = std::max(i_max, i), j_max = std::max(j_max, j), k_max = std::max(k_max, k);
  }
  // Cells numbered in particle order, the same for any thread count. Particles in spatial
  // order (renumbered along a Morton curve) share cells with their predecessors: a repeat of
  // the last key takes the last rank without a probe.
  KeySet occupied(pa.size());
  g.rank_of.assign(pa.size(), -1);
  for (long p = 0, last = -1; p < np; ++p) {
    if (!untied[p]) continue;
    g.rank_of[p] = last >= 0 && cell_of[last] == cell_of[p] ? g.rank_of[last]
                                                             : occupied.insert(cell_of[p]);
    last = p;
  }

  // (rank of the cell's key, face) by block of faces: the blocks' work differs (faces far from
  // every particle cost a box, faces near many a look-up per cell), so the threads take them
  // as they come, and the blocks are joined in order.
  const long nb = blockCount(nf);
  std::vector<ThreadBuffer<std::vector<std::pair<int, int>>>> parts(static_cast<std::size_t>(nb));
  g.entry.resize(faces.size());
#pragma omp parallel for schedule(dynamic, 1) if (nf > kParallelMin)
  for (long b = 0; b < nb; ++b) {
    std::vector<std::pair<int, int>>& mine = parts[static_cast<std::size_t>(b)].items;
    for (long k = nf * b / nb; k < nf * (b + 1) / nb; ++k) {
      const std::size_t first = mine.size();
      Vec3 swept_lo = Vec3::Constant(1e300), swept_hi = Vec3::Constant(-1e300);
      for (int a : faces[k].node) {
        swept_lo = swept_lo.cwiseMin(nd.x[a]).cwiseMin(nd.x[a] + dt * nd.v[a]);
        swept_hi = swept_hi.cwiseMax(nd.x[a]).cwiseMax(nd.x[a] + dt * nd.v[a]);
      }
      const Vec3 lo = swept_lo.array() - reach, hi = swept_hi.array() + reach;
      const long i0 = std::max(g.index(lo.x()), i_min), i1 = std::min(g.index(hi.x()), i_max);
      const long j0 = std::max(g.index(lo.y()), j_min), j1 = std::min(g.index(hi.y()), j_max);
      const long k0 = std::max(g.index(lo.z()), k_min), k1 = std::min(g.index(hi.z()), k_max);
      for (long i = i0; i <= i1; ++i)
        for (long j = j0; j <= j1; ++j)
          for (long l = k0; l <= k1; ++l) {
            // A box can meet the same key twice through a collision: each face once a key.
            const int rank = occupied.rank(FaceGrid::key(i, j, l));
            if (rank >= 0 && std::none_of(mine.begin() + first, mine.end(),
                                          [&](const auto& e) { return e.first == rank; }))
              mine.emplace_back(rank, static_cast<int>(k));
          }
      if (mine.size() == first) continue;
      const Vec3& point = nd.x[faces[k].node[0]];
      const FacePlane plane = facePlane(point, nd.x[faces[k].node[1]], nd.x[faces[k].node[2]]);
      if (!plane.valid()) {  // degenerate: no candidate
        mine.resize(first);
        continue;
      }
      // A hit needs the particle's end position over the face's end triangle widened by the
      // barycentric tolerance (which lies within 1.73 kBaryTolerance L of the triangle, L its
      // longest edge), and within its contact radius in front of it or behind it after a
      // crossing. The end triangle lies in the swept box, and a particle that crosses it
      // from in front ends behind it by at most its reach (radius and travel), so its
      // predicted position lies within reach + 1.73 kBaryTolerance L of the swept box. A
      // second reach leaves room for the passes' corrections, which the cell of the
      // predicted position ignores as well. A face farther than that cannot be hit and is no
      // candidate: in the quick four-plate run at 100 us, 26k candidate faces instead of the
      // cell's 61k, and a sixth fewer particles with any, for the same hits.
      const double margin =
          2 * reach + 2 * kBaryTolerance * std::sqrt(longestEdgeSquared(nd.x, faces[k]));
      g.entry[k] = {point, plane.normal, swept_lo.array() - margin, swept_hi.array() + margin};
    }
  }
  // Counting sort by cell: the parts hold ascending faces in block order, so each cell's row
  // comes out in ascending face order, whatever the thread that entered it.
  g.start.assign(occupied.size() + 1, 0);
  for (const auto& part : parts)
    for (const auto& e : part.items) ++g.start[static_cast<std::size_t>(e.first) + 1];
  for (std::size_t c = 0; c < occupied.size(); ++c) g.start[c + 1] += g.start[c];
  std::vector<std::size_t> fill(g.start.begin(), g.start.end() - 1);
  g.face.resize(g.start.back());
  for (const auto& part : parts)
    for (const auto& [rank, k] : part.items) g.face[fill[static_cast<std::size_t>(rank)]++] = k;
  return g;
}

struct Hit {
  int face = -1;
  double delta = 0;  ///< how far inside the contact radius the particle would end, m
  Vec3 normal = Vec3::Zero();
  Vec3 bary = Vec3::Zero();
};

// The faces of `candidates` that particle p can hit this step, judged on the positions at the
// start of the step, which the passes do not change: the particle projects onto the face and
// is not already behind it (a particle behind a face crossed elsewhere).
// Each comes with the particle's distance to it then, which the passes reuse.
struct Viable {
  int face;
  double distance;  ///< m, from the face's plane at the start of the step
  int slot;         ///< the face's entry in the face ends (FaceEnd) of this step
};

// A face's triangle at the end of the step and its plane, once per face instead of once per
// particle near it.
struct FaceEnd {
  Vec3 a, b, c;  ///< vertices at x + dt v, m
  FacePlane plane;
  long at = -1;  ///< push count when formed (-1: not yet)
};

void formFaceEnd(const Model& model, int face, double dt, long pushes, FaceEnd& e) {
  const Nodes& nd = model.nodes;
  const ExteriorFace& f = model.surfaces.exterior[face];
  e.a = nd.x[f.node[0]] + dt * nd.v[f.node[0]];
  e.b = nd.x[f.node[1]] + dt * nd.v[f.node[1]];
  e.c = nd.x[f.node[2]] + dt * nd.v[f.node[2]];
  e.plane = facePlane(e.a, e.b, e.c);
  e.at = pushes;
}

void viableFaces(const Model& model, std::size_t p, double radius, double dt, const FaceGrid& grid,
                 std::vector<Viable>& out) {
  const Vec3& x = model.particles.x[p];
  const Vec3 y = x + dt * model.particles.v[p];  // predicted position, as for its cell
  const std::size_t r = static_cast<std::size_t>(grid.rank_of[p]);
  for (std::size_t e = grid.start[r]; e < grid.start[r + 1]; ++e) {
    const int k = grid.face[e];
    const FaceGrid::Entry& f = grid.entry[static_cast<std::size_t>(k)];
    if ((y.array() < f.lo.array()).any() || (y.array() > f.hi.array()).any()) continue;
    const double distance = (x - f.point).dot(f.normal);
    if (distance >= -radius) out.push_back({k, distance, -1});
  }
}

// The face particle p (contact radius `radius`) penetrates most at the end of the step, if
// any, among its viable faces. The tests on the distance come before the barycentric weights,
// which only a face within reach needs (most are not).
Hit deepestHit(const Model& model, std::size_t p, double radius, const Viable* viable,
               const Viable* viable_end, const std::vector<FaceEnd>& ends, double dt) {
  const Particles& pa = model.particles;
  const Vec3 xp = pa.x[p] + dt * pa.v[p];
  Hit best;
  for (const Viable* it = viable; it != viable_end; ++it) {
    const FaceEnd& e = ends[static_cast<std::size_t>(it->slot)];
    if (!e.plane.valid()) continue;
    const double distance = (xp - e.a).dot(e.plane.normal);
    // A particle already inside its radius (born next to faces, or left there by earlier
    // steps) is only kept from coming closer: pushing it out in one step would need a velocity
    // of overlap/dt and throw it away.
    if (distance >= radius) continue;
    const double delta = it->distance >= radius ? radius - distance : it->distance - distance;
    if (delta <= 0 || delta <= best.delta) continue;
    // It must end within the face's extent.
    const Vec3 bary = baryInPlane(xp - distance * e.plane.normal, e.a, e.b, e.c, e.plane);
    if (bary.minCoeff() < -kBaryTolerance) continue;
    best = Hit{it->face, delta, e.plane.normal, clampBary(bary)};
  }
  return best;
}

// The impulse of `hit` on particle p and the face's nodes.
void applyHit(Model& model, std::size_t p, const Hit& hit, double alpha, double dt) {
  Particles& pa = model.particles;
  Nodes& nd = model.nodes;
  const ExteriorFace& f = model.surfaces.exterior[hit.face];
  double denom = 1.0 / pa.m[p];
  for (int i = 0; i < 3; ++i) denom += hit.bary[i] * hit.bary[i] * nd.inverseMass(f.node[i]);
  const double impulse = alpha * hit.delta / dt / denom;
  pa.v[p] += (impulse / pa.m[p]) * hit.normal;
  for (int i = 0; i < 3; ++i)
    nd.addVelocity(f.node[i], (-hit.bary[i] * impulse * nd.inverseMass(f.node[i])) * hit.normal);
}

// Buffers kept from call to call: taken afresh (~2 MB late in the quick run), their page faults
// and zero fills were ~1 % of the run, serial.
struct Scratch {
  std::vector<ThreadBuffer<std::vector<Viable>>> parts;  ///< viable faces by block of particles
  std::vector<Viable> viable;
  std::vector<FaceEnd> ends;
  std::vector<Hit> hits;
};

// The calling thread's Scratch: the thread that steps the model (the parallel regions run
// inside the calls), so one per run, reused by every call.
Scratch& threadScratch() {
  thread_local Scratch scratch;
  return scratch;
}

// The face slots that hold each node (compressed rows over the nodes): the slots a push on a
// node makes stale, and the slots the sweep groups join.
struct NodeSlots {
  std::vector<std::size_t> at;  ///< node a's slots are slots[at[a]] .. slots[at[a + 1] - 1]
  std::vector<int> slots;
  std::size_t n_slots = 0;      ///< the slots' count
};

NodeSlots nodeSlots(const Model& model, const std::vector<int>& slot_face) {
  const auto& faces = model.surfaces.exterior;
  NodeSlots n;
  n.n_slots = slot_face.size();
  n.at.assign(model.nodes.size() + 1, 0);
  for (int f : slot_face)
    for (int a : faces[static_cast<std::size_t>(f)].node) ++n.at[static_cast<std::size_t>(a) + 1];
  for (std::size_t a = 0; a < model.nodes.size(); ++a) n.at[a + 1] += n.at[a];
  n.slots.resize(n.at.back());
  std::vector<std::size_t> fill(n.at.begin(), n.at.end() - 1);
  for (std::size_t s = 0; s < slot_face.size(); ++s)
    for (int a : faces[static_cast<std::size_t>(slot_face[s])].node)
      n.slots[fill[static_cast<std::size_t>(a)]++] = static_cast<int>(s);
  return n;
}

// The candidates (indices into `candidates`) in groups that share no face node: members
// ascending within a group, the groups largest first (the order the threads take them in,
// which changes no result). One thread takes them all as one group, without the grouping.
struct SweepGroups {
  std::vector<long> members;
  std::vector<std::size_t> start;  ///< group g's members are [start[g], start[g + 1])
  std::vector<std::size_t> order;
};

SweepGroups sweepGroups(const std::vector<int>& candidates, const std::vector<std::size_t>& offset,
                        const std::vector<Viable>& viable, const NodeSlots& node_slots) {
  SweepGroups g;
  if (maxThreads() == 1 || candidates.size() <= static_cast<std::size_t>(kParallelMin)) {
    g.members.resize(candidates.size());
    std::iota(g.members.begin(), g.members.end(), 0L);
    g.start = {0, candidates.size()};
    g.order = {0};
    return g;
  }
  // Disjoint sets of face slots: slots that share a node, and the viable slots of a candidate.
  // The sets are the connected components, whoever joins them: the joins (~60k late in the
  // quick run, 1.7 % of it when serial) go to a copy per share of the nodes and candidates,
  // and the copies are joined into the first (a share's set, slot by slot).
  const std::size_t n_slots = node_slots.n_slots;
  const long shares = maxThreads(), nc = static_cast<long>(candidates.size());
  const long nn = static_cast<long>(node_slots.at.size()) - 1;
  std::vector<UnionFind> share(static_cast<std::size_t>(shares), UnionFind(n_slots));
#pragma omp parallel for schedule(static)
  for (long t = 0; t < shares; ++t) {
    UnionFind& mine = share[static_cast<std::size_t>(t)];
    for (long a = nn * t / shares; a < nn * (t + 1) / shares; ++a)
      for (std::size_t q = node_slots.at[a] + 1; q < node_slots.at[a + 1]; ++q)
        mine.join(node_slots.slots[q], node_slots.slots[node_slots.at[a]]);
    for (long c = nc * t / shares; c < nc * (t + 1) / shares; ++c) {
      const std::size_t p = static_cast<std::size_t>(candidates[c]);
      const int anchor = viable[offset[p]].slot;
      for (std::size_t v = offset[p] + 1; v < offset[p + 1]; ++v) mine.join(viable[v].slot, anchor);
    }
  }
  UnionFind& joined = share[0];
  for (long t = 1; t < shares; ++t)
    for (std::size_t s = 0; s < n_slots; ++s) joined.join(static_cast<int>(s), share[t].find(s));
  // Groups by root slot, ascending, members ascending: a counting sort by root.
  std::vector<int> root_of(candidates.size());
#pragma omp parallel for schedule(static)
  for (long c = 0; c < nc; ++c) root_of[c] = joined.root(viable[offset[candidates[c]]].slot);
  std::vector<std::size_t> fill(n_slots + 1, 0);
  for (int root : root_of) ++fill[static_cast<std::size_t>(root) + 1];
  for (std::size_t s = 0; s < n_slots; ++s) {
    if (fill[s + 1] > 0) g.start.push_back(fill[s]);
    fill[s + 1] += fill[s];
  }
  g.start.push_back(candidates.size());
  g.members.resize(candidates.size());
  for (std::size_t c = 0; c < candidates.size(); ++c)
    g.members[fill[static_cast<std::size_t>(root_of[c])]++] = static_cast<long>(c);
  g.order.resize(g.start.size() - 1);
  std::iota(g.order.begin(), g.order.end(), std::size_t{0});
  std::stable_sort(g.order.begin(), g.order.end(), [&](std::size_t a, std::size_t b) {
    return g.start[a + 1] - g.start[a] > g.start[b + 1] - g.start[b];
  });
  return g;
}

}  // namespace

void enforceParticleFaceContact(Model& model, double dt, int passes) {
  Particles& pa = model.particles;
  const auto& faces = model.surfaces.exterior;
  if (pa.size() == 0 || faces.empty() || !(dt > 0)) return;
  const long np = static_cast<long>(pa.size());

  std::vector<double> radius(pa.size());  // contact radii
  double reach = 0;
#pragma omp parallel for schedule(static) reduction(max : reach) if (np > kParallelMin)
  for (long p = 0; p < np; ++p) {
    radius[p] = kParticleContactRadius * std::cbrt(pa.V[p]);
    reach = std::max(reach, radius[p] + dt * pa.v[p].norm());
  }
  const FaceGrid grid = buildGrid(model, dt, reach);

  // The grid cell of a particle is the one of its predicted position before the passes (the
  // corrections are far smaller than a cell), so its viable faces are found once, by blocks
  // of particles joined in particle order.
  std::vector<std::size_t> offset(pa.size() + 1, 0);
  Scratch& scratch = threadScratch();
  std::vector<Viable>& viable = scratch.viable;
  const long nb = blockCount(np);  // tied particles take no time: blocks, not halves
  auto& parts = scratch.parts;
  parts.resize(static_cast<std::size_t>(nb));
#pragma omp parallel for schedule(dynamic, 1) if (np > kParallelMin)
  for (long b = 0; b < nb; ++b) {
    std::vector<Viable>& mine = parts[static_cast<std::size_t>(b)].items;
    mine.clear();
    for (long p = np * b / nb; p < np * (b + 1) / nb; ++p) {
      const std::size_t before = mine.size();
      if (grid.rank_of[p] >= 0)  // not tied
        viableFaces(model, static_cast<std::size_t>(p), radius[p], dt, grid, mine);
      offset[p + 1] = mine.size() - before;
    }
  }
  for (std::size_t p = 0; p < pa.size(); ++p) offset[p + 1] += offset[p];
  std::vector<int> candidates;  // particles with viable faces, ascending
  for (std::size_t p = 0; p < pa.size(); ++p)
    if (offset[p + 1] > offset[p]) candidates.push_back(static_cast<int>(p));
  if (candidates.empty()) return;

  // The blocks' lists copied into place side by side (~60k entries late in the quick run,
  // where the serial copy was 1.5 % of the run), marking the faces viable for some particle.
  viable.resize(offset.back());
  std::vector<char> is_viable(faces.size(), 0);
#pragma omp parallel for schedule(dynamic, 1) if (np > kParallelMin)
  for (long b = 0; b < nb; ++b) {
    const std::vector<Viable>& mine = parts[static_cast<std::size_t>(b)].items;
    std::copy(mine.begin(), mine.end(), viable.begin() + offset[np * b / nb]);
    for (const Viable& v : mine) {
#pragma omp atomic write
      is_viable[static_cast<std::size_t>(v.face)] = 1;
    }
  }

  // Each face that is viable for some particle gets one slot of face ends, in face order.
  std::vector<int> slot_of(faces.size(), -1);
  std::vector<int> slot_face;
  for (std::size_t f = 0; f < faces.size(); ++f)
    if (is_viable[f]) {
      slot_of[f] = static_cast<int>(slot_face.size());
      slot_face.push_back(static_cast<int>(f));
    }
  const long nv = static_cast<long>(viable.size());
#pragma omp parallel for schedule(static) if (nv > kParallelMin)
  for (long v = 0; v < nv; ++v) viable[v].slot = slot_of[static_cast<std::size_t>(viable[v].face)];

  // A particle's deepest hit depends on its own velocity and the velocities of its viable
  // faces' nodes only, and its own velocity changes only with a hit on one of those faces. So
  // a hit (or a face end) found once stays right until one of those nodes is pushed: every
  // push is stamped on the faces (slots) that hold the pushed face's nodes, and what is older
  // than its faces' stamps is found again. Each pass renews the stale face ends and hits in
  // parallel, then sweeps the particles in particle order (particles share face nodes),
  // renewing those made stale earlier in the sweep.
  const long nc = static_cast<long>(candidates.size());
  const long ns = static_cast<long>(slot_face.size());
  std::vector<FaceEnd>& ends = scratch.ends;  // formed in the first pass
  ends.resize(slot_face.size());
  std::vector<Hit>& hits = scratch.hits;  // found in the first pass
  hits.resize(candidates.size());
  std::vector<long> found_at(candidates.size(), -1);  // push count when the hit was found
  // The newest push among each slot's nodes, set on every push through the slots of the
  // pushed nodes: a slot's staleness is then one look-up, where it took its face's three
  // nodes' stamps (checked ~26 times a candidate per pass).
  std::vector<long> slot_pushed(slot_face.size(), -1);
  const NodeSlots node_slots = nodeSlots(model, slot_face);
  long pushes = 0;
  const auto staleSince = [&](int slot, long at) {
    return at < 0 || slot_pushed[static_cast<std::size_t>(slot)] >= at;
  };
  const auto renewEnd = [&](long s, long now) {
    if (staleSince(static_cast<int>(s), ends[s].at))
      formFaceEnd(model, slot_face[s], dt, now, ends[s]);
  };
  // The face ends must be fresh (renewEnd) for the viable faces of candidate c.
  const auto renewHit = [&](long c, long now) {
    const std::size_t p = static_cast<std::size_t>(candidates[c]);
    const Viable* first = viable.data() + offset[p];
    const Viable* last = viable.data() + offset[p + 1];
    bool stale = found_at[c] < 0;
    for (const Viable* it = first; !stale && it != last; ++it)
      stale = staleSince(it->slot, found_at[c]);
    if (!stale) return;
    hits[c] = deepestHit(model, p, radius[p], first, last, ends, dt);
    found_at[c] = now;
  };

  // A push moves the pusher's own particle and the nodes of one of its viable faces, so
  // candidates whose viable faces share no node never see each other's pushes. Grouped by
  // shared nodes, the groups are swept side by side, each in ascending candidate order and
  // counting its own pushes from the pass's start: within a group that orders pushes and
  // finds as the one sweep over all candidates did, and no stamp is ever compared across
  // groups, so the result is that sweep's bit for bit, for any thread count.
  const SweepGroups groups = sweepGroups(candidates, offset, viable, node_slots);
  const long ng = static_cast<long>(groups.order.size());
  // The first candidate of thread t of nt: one block per thread, the blocks holding equal
  // numbers of viable faces (what a hit costs). Fixed blocks, not a dynamic schedule: small
  // chunks handed out in turn cost an atomic each and shared the cache lines of hits and
  // stamps at every chunk's edge (the first pass's hits took as long on two threads as on one).
  const auto hitBlock = [&](long t, long nt) -> long {
    if (t == 0 || t == nt) return t == 0 ? 0 : nc;
    const std::size_t share =
        viable.size() * static_cast<std::size_t>(t) / static_cast<std::size_t>(nt);
    return std::lower_bound(candidates.begin(), candidates.end(), share,
                            [&](int p, std::size_t v) { return offset[p] < v; }) -
           candidates.begin();
  };
  for (int k = 1; k <= passes; ++k) {
    const double alpha = 1.0 / std::sqrt(static_cast<double>(passes - k + 1));
#pragma omp parallel if (nc > kParallelMin)
    {
#pragma omp for schedule(static)
      for (long s = 0; s < ns; ++s) {
        if (k == 1) ends[s].at = -1;  // left from the last call
        renewEnd(s, pushes);
      }
      const long nt = teamSize(), t = threadId();
      for (long c = hitBlock(t, nt); c < hitBlock(t + 1, nt); ++c) renewHit(c, pushes);
    }
    const long pushes_before = pushes;
    long pushed = 0;
#pragma omp parallel for schedule(dynamic, 1) reduction(+ : pushed) if (nc > kParallelMin)
    for (long gi = 0; gi < ng; ++gi) {
      const std::size_t g = groups.order[static_cast<std::size_t>(gi)];
      long now = pushes_before;
      for (std::size_t m = groups.start[g]; m < groups.start[g + 1]; ++m) {
        const long c = groups.members[m];
        if (now > pushes_before) {
          const std::size_t p = static_cast<std::size_t>(candidates[c]);
          for (std::size_t v = offset[p]; v < offset[p + 1]; ++v) renewEnd(viable[v].slot, now);
          renewHit(c, now);
        }
        if (hits[c].face < 0) continue;
        applyHit(model, static_cast<std::size_t>(candidates[c]), hits[c], alpha, dt);
        for (int a : faces[hits[c].face].node)  // the slots sharing a node share its group
          for (std::size_t q = node_slots.at[a]; q < node_slots.at[a + 1]; ++q)
            slot_pushed[static_cast<std::size_t>(node_slots.slots[q])] = now;
        ++now;
      }
      pushed += now - pushes_before;
    }
    pushes = pushes_before + pushed;  // above every stamp of this pass
    if (pushed == 0) break;
  }
}

std::size_t particleFaceContactScratchBytes() {
  const Scratch& s = threadScratch();
  return heapBytes(s.parts, s.viable, s.ends, s.hits);
}

}  // namespace fesph
