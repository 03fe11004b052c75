// SPDX-License-Identifier: MIT
#include "core/scene/initial_overlap.hpp"

#include <Eigen/LU>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>
#include <vector>

namespace fesph {

namespace {

struct Box {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 hi = -lo;
  void add(const Vec3& p) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  bool contains(const Vec3& p) const {
    return (p.array() >= lo.array()).all() && (p.array() <= hi.array()).all();
  }
  bool meets(const Box& o) const {
    return (lo.array() <= o.hi.array()).all() && (o.lo.array() <= hi.array()).all();
  }
};

// A body's points: its nodes, or the particles of a particle body.
std::vector<Vec3> pointsOf(const Model& model, int b) {
  const Body& body = model.bodies[static_cast<std::size_t>(b)];
  std::vector<Vec3> points(model.nodes.x.begin() + static_cast<std::ptrdiff_t>(body.node_begin),
                           model.nodes.x.begin() + static_cast<std::ptrdiff_t>(body.node_end));
  for (std::size_t i = 0; i < model.particles.size(); ++i)
    if (model.particles.body[i] == b) points.push_back(model.particles.x[i]);
  return points;
}

// The elements of one body on a uniform grid (cell: their mean largest extent), each entered
// in every cell its box meets; a point is tested against the elements of its cell only.
class ElementGrid {
 public:
  ElementGrid(const Model& model, const Body& body, const Box& bounds)
      : model_(model), origin_(bounds.lo) {
    double extent = 0;
    for (std::size_t e = body.elem_begin; e < body.elem_end; ++e) {
      const Box box = elementBox(e);
      extent += (box.hi - box.lo).maxCoeff();
    }
    cell_ = extent / static_cast<double>(body.elem_end - body.elem_begin);
    if (!(cell_ > 0)) cell_ = 1;  // flat elements only (finaliseModel refuses them first)
    for (std::size_t e = body.elem_begin; e < body.elem_end; ++e) {
      const Box box = elementBox(e);
      const auto lo = index(box.lo), hi = index(box.hi);
      for (long i = lo[0]; i <= hi[0]; ++i)
        for (long j = lo[1]; j <= hi[1]; ++j)
          for (long k = lo[2]; k <= hi[2]; ++k) entries_.emplace_back(key(i, j, k), e);
    }
    std::sort(entries_.begin(), entries_.end());
  }

  /// Whether p lies inside the body: in one of its elements (closed), and on none of its
  /// exterior faces. A point on an internal face, edge or node is in no element strictly, so
  /// "strictly inside an element" would miss it; a point on the surface touches, as bodies
  /// placed face to face do.
  bool inside(const Vec3& p) const {
    const auto c = index(p);
    const std::uint64_t k = key(c[0], c[1], c[2]);
    bool in_element = false;
    auto it = std::lower_bound(entries_.begin(), entries_.end(), std::make_pair(k, std::size_t{0}));
    for (; it != entries_.end() && it->first == k; ++it) {
      const std::size_t e = it->second;
      const std::array<double, 4> l = barycentric(e, p);
      if (*std::min_element(l.begin(), l.end()) < -kTolerance) continue;
      for (int corner = 0; corner < 4; ++corner)
        if (std::abs(l[corner]) <= kTolerance && onSurface(e, corner)) return false;
      in_element = true;
    }
    return in_element;
  }

 private:
  Box elementBox(std::size_t e) const {
    Box box;
    for (int a : model_.elems.conn[e]) box.add(model_.nodes.x[static_cast<std::size_t>(a)]);
    return box;
  }
  std::array<long, 3> index(const Vec3& p) const {
    std::array<long, 3> c{};
    for (int d = 0; d < 3; ++d) c[d] = std::lround(std::floor((p[d] - origin_[d]) / cell_));
    return c;
  }
  static std::uint64_t key(long i, long j, long k) {
    return (static_cast<std::uint64_t>(i) & 0x1FFFFF) << 42 |
           (static_cast<std::uint64_t>(j) & 0x1FFFFF) << 21 |
           (static_cast<std::uint64_t>(k) & 0x1FFFFF);
  }
  // Barycentric coordinates of p in element e, one per corner (l[k] = 0 on the face opposite
  // corner k); all in [0, 1] within the tolerance: p in the element.
  std::array<double, 4> barycentric(std::size_t e, const Vec3& p) const {
    const auto& n = model_.elems.conn[e];
    const Vec3& x0 = model_.nodes.x[static_cast<std::size_t>(n[0])];
    Mat3 edges;
    for (int a = 0; a < 3; ++a)
      edges.col(a) = model_.nodes.x[static_cast<std::size_t>(n[a + 1])] - x0;
    const Vec3 l = edges.inverse() * (p - x0);
    return {1.0 - l.sum(), l[0], l[1], l[2]};
  }
  // Whether element e's face opposite `corner` is on the body's surface.
  bool onSurface(std::size_t e, int corner) const {
    const Surfaces& s = model_.surfaces;
    return s.table[static_cast<std::size_t>(s.elem_faces[e][corner])].exterior >= 0;
  }

  static constexpr double kTolerance = 1e-9;  ///< of a barycentric coordinate
  const Model& model_;
  Vec3 origin_;
  double cell_ = 1;
  std::vector<std::pair<std::uint64_t, std::size_t>> entries_;  ///< (cell key, element)
};

}  // namespace

std::optional<InitialOverlap> findInitialOverlap(const Model& model) {
  const int nb = static_cast<int>(model.bodies.size());
  std::vector<std::vector<Vec3>> points(static_cast<std::size_t>(nb));
  std::vector<Box> bounds(static_cast<std::size_t>(nb));
  for (int b = 0; b < nb; ++b) {
    points[b] = pointsOf(model, b);
    for (const Vec3& p : points[b]) bounds[b].add(p);
  }
  for (int outer = 0; outer < nb; ++outer) {
    const Body& body = model.bodies[static_cast<std::size_t>(outer)];
    if (body.elem_end == body.elem_begin) continue;
    std::optional<ElementGrid> grid;  // built only when another body's bounds meet its own
    for (int inner = 0; inner < nb; ++inner) {
      if (inner == outer || !bounds[inner].meets(bounds[outer])) continue;
      if (!grid) grid.emplace(model, body, bounds[outer]);
      InitialOverlap o{inner, outer, 0, Vec3::Zero()};
      for (const Vec3& p : points[inner]) {
        if (!bounds[outer].contains(p) || !grid->inside(p)) continue;
        if (o.points == 0) o.example = p;
        ++o.points;
      }
      if (o.points > 0) return o;
    }
  }
  return std::nullopt;
}

}  // namespace fesph
