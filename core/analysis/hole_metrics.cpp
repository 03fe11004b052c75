// SPDX-License-Identifier: MIT
// Hole metrics: project the plate's live tets (or its particles, as discs) onto its mid-plane,
// rasterise, and take the empty 4-connected regions that do not reach the raster border as
// through-holes.
#include "core/analysis/hole_metrics.hpp"

#include "core/analysis/debris.hpp"
#include "core/common/error.hpp"
#include "core/common/union_find.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <map>
#include <stdexcept>
#include <utility>

namespace fesph {

namespace {

constexpr double kPi = 3.14159265358979323846;

// Tets of the largest node-connected piece (union-find over the nodes of each tet).
std::vector<std::size_t> largestPiece(std::size_t n_points,
                                      const std::vector<std::array<int, 4>>& tets) {
  UnionFind sets(n_points);
  for (const auto& t : tets)
    for (int k = 1; k < 4; ++k) sets.join(t[k], t[0]);
  std::vector<std::size_t> count(n_points, 0);
  for (const auto& t : tets) ++count[sets.find(t[0])];
  const int root = static_cast<int>(std::max_element(count.begin(), count.end()) - count.begin());
  std::vector<std::size_t> kept;
  for (std::size_t e = 0; e < tets.size(); ++e)
    if (sets.find(tets[e][0]) == root) kept.push_back(e);
  return kept;
}

Vec3 mirrored(const Vec3& p, const HoleOptions& o) {
  Vec3 q = p;
  q[o.symmetry_axis] = 2 * o.symmetry_position - p[o.symmetry_axis];
  return q;
}

// Mid-plane frame: normal from PCA (or given), v = global y projected into the plane.
void setFrame(const std::vector<Vec3>& pts, const HoleOptions& o, PlateHoles& out) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : pts) mean += p;
  mean /= static_cast<double>(pts.size());
  Vec3 n = o.normal;
  if (n.norm() == 0) {
    Mat3 cov = Mat3::Zero();
    for (const Vec3& p : pts) cov += (p - mean) * (p - mean).transpose();
    const Eigen::SelfAdjointEigenSolver<Mat3> eig(cov);
    n = eig.eigenvectors().col(0);  // smallest eigenvalue first
    Eigen::Index big;
    n.cwiseAbs().maxCoeff(&big);
    if (n[big] < 0) n = -n;  // a z-normal plate faces +z, where projectiles come from
  }
  n.normalize();
  Vec3 v = Vec3::UnitY() - Vec3::UnitY().dot(n) * n;
  if (v.norm() < 0.1) v = Vec3::UnitX() - Vec3::UnitX().dot(n) * n;
  v.normalize();
  out.normal = n;
  out.v = v;
  out.u = v.cross(n);
  double lo = 1e300, hi = -1e300;
  for (const Vec3& p : pts) {
    const double s = (p - mean).dot(n);
    lo = std::min(lo, s);
    hi = std::max(hi, s);
  }
  out.origin = mean + 0.5 * (lo + hi) * n;
  out.front = 0.5 * (hi - lo);
  out.rear = -out.front;
}

double defaultCellSize(const std::vector<Vec3>& x, const std::vector<std::array<int, 4>>& tets,
                       const std::vector<std::size_t>& kept) {
  std::vector<double> len;
  len.reserve(kept.size() * 6);
  for (std::size_t e : kept)
    for (int a = 0; a < 4; ++a)
      for (int b = a + 1; b < 4; ++b) len.push_back((x[tets[e][a]] - x[tets[e][b]]).norm());
  auto p10 = len.begin() + static_cast<std::ptrdiff_t>(len.size() / 10);
  std::nth_element(len.begin(), p10, len.end());
  return *p10 / 4;
}

struct Raster {
  double a0 = 0, b0 = 0, h = 0;  // corner of cell (0, 0) and cell edge
  int nx = 0, ny = 0;
  std::vector<std::uint8_t> full;
  std::size_t at(int i, int j) const { return static_cast<std::size_t>(j) * nx + i; }
  double ca(int i) const { return a0 + (i + 0.5) * h; }
  double cb(int j) const { return b0 + (j + 0.5) * h; }

  // Mark cells whose centre lies in the disc (its edge included).
  void fillDisc(const Eigen::Vector2d& c, double radius) {
    const int i0 = std::max(0, static_cast<int>(std::floor((c.x() - radius - a0) / h)));
    const int i1 = std::min(nx - 1, static_cast<int>(std::floor((c.x() + radius - a0) / h)));
    const int j0 = std::max(0, static_cast<int>(std::floor((c.y() - radius - b0) / h)));
    const int j1 = std::min(ny - 1, static_cast<int>(std::floor((c.y() + radius - b0) / h)));
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const double dx = ca(i) - c.x(), dy = cb(j) - c.y();
        if (dx * dx + dy * dy <= radius * radius) full[at(i, j)] = 1;
      }
  }

  // Mark cells whose centre lies in the triangle (edges included, so shared edges leave no gap).
  void fillTriangle(const Eigen::Vector2d& p, const Eigen::Vector2d& q, const Eigen::Vector2d& r) {
    const double area2 = (q - p).x() * (r - p).y() - (q - p).y() * (r - p).x();
    if (std::abs(area2) < 1e-30) return;
    const double tol = -1e-9 * std::abs(area2);
    const int i0 = std::max(0, static_cast<int>(std::floor((std::min({p.x(), q.x(), r.x()}) - a0) / h)));
    const int i1 = std::min(nx - 1, static_cast<int>(std::floor((std::max({p.x(), q.x(), r.x()}) - a0) / h)));
    const int j0 = std::max(0, static_cast<int>(std::floor((std::min({p.y(), q.y(), r.y()}) - b0) / h)));
    const int j1 = std::min(ny - 1, static_cast<int>(std::floor((std::max({p.y(), q.y(), r.y()}) - b0) / h)));
    const double s = area2 > 0 ? 1.0 : -1.0;
    const auto edge = [](const Eigen::Vector2d& a, const Eigen::Vector2d& b, double x, double y) {
      return (b.x() - a.x()) * (y - a.y()) - (b.y() - a.y()) * (x - a.x());
    };
    for (int j = j0; j <= j1; ++j)
      for (int i = i0; i <= i1; ++i) {
        const double x = ca(i), y = cb(j);
        if (s * edge(p, q, x, y) >= tol && s * edge(q, r, x, y) >= tol &&
            s * edge(r, p, x, y) >= tol)
          full[at(i, j)] = 1;
      }
  }
};

// Outline of one region: its outer boundary, the cell edges with the region on their left
// chained into one loop from the lowest corner (which lies on the outer boundary), staircase
// corners cut. Where two of the region's cells meet only at a corner, the chain keeps to the
// cell it came along (a left turn): the region is 4-connected, so those cells are not joined
// there, and the loop stays one simple loop whatever the order the edges were found in.
// Loops round islands (plate cells the region surrounds) are not the outline.
std::vector<Eigen::Vector2d> outlineOf(const Raster& r, const std::vector<int>& label, int id,
                                       const std::vector<std::size_t>& cells) {
  using Corner = std::pair<int, int>;
  std::multimap<Corner, Corner> edges;
  const auto other = [&](int a, int b) {
    return a < 0 || b < 0 || a >= r.nx || b >= r.ny || label[r.at(a, b)] != id;
  };
  for (std::size_t c : cells) {
    const int i = static_cast<int>(c % r.nx), j = static_cast<int>(c / r.nx);
    if (other(i, j - 1)) edges.emplace(Corner{i, j}, Corner{i + 1, j});
    if (other(i + 1, j)) edges.emplace(Corner{i + 1, j}, Corner{i + 1, j + 1});
    if (other(i, j + 1)) edges.emplace(Corner{i + 1, j + 1}, Corner{i, j + 1});
    if (other(i - 1, j)) edges.emplace(Corner{i, j + 1}, Corner{i, j});
  }
  std::vector<Corner> loop;
  const Corner start = edges.begin()->first;
  Corner from = start, at = start;
  do {
    loop.push_back(at);
    auto [first, last] = edges.equal_range(at);
    if (first == last) throw std::logic_error("hole outline: a boundary edge chain is open");
    auto next = first;
    for (auto it = first; it != last; ++it) {  // two ways on only where cells meet at a corner
      const Corner step{it->second.first - at.first, it->second.second - at.second};
      const Corner came{at.first - from.first, at.second - from.second};
      if (step == Corner{-came.second, came.first}) next = it;  // the left turn
    }
    from = at;
    at = next->second;
    edges.erase(next);
  } while (at != start);
  // The midpoints of the boundary's cell edges: the staircase with every step's corner cut by
  // half a cell, so an even run of steps becomes a straight line and a straight side stays
  // one. Cutting only at the turns (the midpoints of whole sides) made a square hole a
  // diamond of half its area. Then only the points where the direction changes.
  const std::size_t n = loop.size();
  std::vector<Corner> mid(n);  // twice the midpoints: whole numbers, exact collinearity
  for (std::size_t k = 0; k < n; ++k)
    mid[k] = {loop[k].first + loop[(k + 1) % n].first, loop[k].second + loop[(k + 1) % n].second};
  std::vector<Eigen::Vector2d> pts;
  for (std::size_t k = 0; k < n; ++k) {
    const Corner& a = mid[(k + n - 1) % n];
    const Corner& b = mid[k];
    const Corner& c = mid[(k + 1) % n];
    const bool straight = (b.first - a.first) * (c.second - b.second) ==
                          (b.second - a.second) * (c.first - b.first);
    if (!straight) pts.emplace_back(r.a0 + 0.5 * b.first * r.h, r.b0 + 0.5 * b.second * r.h);
  }
  return pts;
}

// A raster over the plate's in-plane extent (out.u_min .. v_max) with two empty cells of
// margin, so the region outside the plate is one piece touching the border. The cell is `h`,
// or larger where the extent would take more than options.max_cells.
Raster rasterOver(PlateHoles& out, double h, const HoleOptions& o) {
  const double cells = (out.u_max - out.u_min) * (out.v_max - out.v_min) / (h * h);
  if (cells > static_cast<double>(o.max_cells)) h *= std::sqrt(cells / o.max_cells);
  out.cell_size = h;
  Raster r;
  r.h = h;
  r.a0 = out.u_min - 2 * h;
  r.b0 = out.v_min - 2 * h;
  r.nx = static_cast<int>(std::ceil((out.u_max - out.u_min) / h)) + 4;
  r.ny = static_cast<int>(std::ceil((out.v_max - out.v_min) / h)) + 4;
  r.full.assign(static_cast<std::size_t>(r.nx) * r.ny, 0);
  return r;
}

// The through-holes of a filled raster: its empty 4-connected regions that do not reach the
// border, of at least the smallest area, largest first, into out.holes.
void collectHoles(const Raster& r, const HoleOptions& o, PlateHoles& out) {
  // Label the empty regions (4-connected); label 0 is the outside, reached from the border.
  std::vector<int> label(r.full.size(), -1);
  std::vector<std::vector<std::size_t>> regions;  // cells of each region (none kept for 0)
  std::vector<std::size_t> stack;
  const auto flood = [&](int i, int j) {
    const int id = static_cast<int>(regions.size());
    regions.emplace_back();
    stack.push_back(r.at(i, j));
    label[r.at(i, j)] = id;
    while (!stack.empty()) {
      const std::size_t c = stack.back();
      stack.pop_back();
      if (id > 0) regions.back().push_back(c);
      const int ci = static_cast<int>(c % r.nx), cj = static_cast<int>(c / r.nx);
      const int ni[4] = {ci - 1, ci + 1, ci, ci}, nj[4] = {cj, cj, cj - 1, cj + 1};
      for (int k = 0; k < 4; ++k) {
        if (ni[k] < 0 || nj[k] < 0 || ni[k] >= r.nx || nj[k] >= r.ny) continue;
        const std::size_t d = r.at(ni[k], nj[k]);
        if (r.full[d] || label[d] >= 0) continue;
        label[d] = id;
        stack.push_back(d);
      }
    }
  };
  flood(0, 0);
  for (int j = 0; j < r.ny; ++j)
    for (int i = 0; i < r.nx; ++i)
      if (!r.full[r.at(i, j)] && label[r.at(i, j)] < 0) flood(i, j);

  const double cell_area = r.h * r.h;
  const double min_area = o.min_area > 0 ? o.min_area : 4 * cell_area;
  const auto at3d = [&](double a, double b) { return Vec3(out.origin + a * out.u + b * out.v); };
  for (std::size_t id = 1; id < regions.size(); ++id) {
    const std::vector<std::size_t>& cells = regions[id];
    const double area = static_cast<double>(cells.size()) * cell_area;
    if (area < min_area) continue;
    Hole hole;
    hole.area = area;
    hole.diameter = std::sqrt(4 * area / kPi);
    double sa = 0, sb = 0;
    bool below = false, above = false;
    for (std::size_t c : cells) {
      const int i = static_cast<int>(c % r.nx), j = static_cast<int>(c / r.nx);
      sa += r.ca(i);
      sb += r.cb(j);
      if (o.mirror) {
        const double side = at3d(r.ca(i), r.cb(j))[o.symmetry_axis] - o.symmetry_position;
        below |= side < 0;
        above |= side > 0;
      }
    }
    hole.centroid = at3d(sa / cells.size(), sb / cells.size());
    hole.on_symmetry = below && above;
    for (const Eigen::Vector2d& p : outlineOf(r, label, static_cast<int>(id), cells))
      hole.outline.push_back(at3d(p.x(), p.y()));
    out.holes.push_back(std::move(hole));
  }
  std::sort(out.holes.begin(), out.holes.end(),
            [](const Hole& a, const Hole& b) { return a.area > b.area; });
}

}  // namespace

PlateHoles findHoles(const std::vector<Vec3>& x, const std::vector<std::array<int, 4>>& tets,
                     const HoleOptions& o) {
  PlateHoles out;
  if (tets.empty()) return out;
  const std::vector<std::size_t> kept = largestPiece(x.size(), tets);

  std::vector<Vec3> pts;  // nodes of the kept tets, and their mirror images
  {
    std::vector<char> used(x.size(), 0);
    for (std::size_t e : kept)
      for (int n : tets[e]) used[n] = 1;
    for (std::size_t n = 0; n < x.size(); ++n)
      if (used[n]) {
        pts.push_back(x[n]);
        if (o.mirror) pts.push_back(mirrored(x[n], o));
      }
  }
  setFrame(pts, o, out);
  out.u_min = out.v_min = 1e300;
  out.u_max = out.v_max = -1e300;
  for (const Vec3& p : pts) {
    const Eigen::Vector2d q = out.inPlane(p);
    out.u_min = std::min(out.u_min, q.x()), out.u_max = std::max(out.u_max, q.x());
    out.v_min = std::min(out.v_min, q.y()), out.v_max = std::max(out.v_max, q.y());
  }
  Raster r = rasterOver(out, o.cell_size > 0 ? o.cell_size : defaultCellSize(x, tets, kept), o);
  for (int copy = 0; copy < (o.mirror ? 2 : 1); ++copy)
    for (std::size_t e : kept) {
      Eigen::Vector2d q[4];
      for (int k = 0; k < 4; ++k) {
        const Vec3& p = x[tets[e][k]];
        q[k] = out.inPlane(copy == 0 ? p : mirrored(p, o));
      }
      // The projected tet is the hull of its four projected corners, which the three faces
      // at any one corner cover (a fan from a corner of the hull, or around it when inside).
      r.fillTriangle(q[0], q[1], q[2]);
      r.fillTriangle(q[0], q[1], q[3]);
      r.fillTriangle(q[0], q[2], q[3]);
    }
  collectHoles(r, o, out);
  return out;
}

PlateHoles findParticleHoles(const std::vector<DebrisParticle>& particles, const HoleOptions& o,
                             std::vector<int>* proper) {
  PlateHoles out;
  if (proper) proper->clear();
  // The plate proper: the largest clump of its unfailed particles. A failed particle (damage
  // 1) is debris, as a failed element is eroded: a cloud of them ahead of the projectile stays
  // linked to the rim in chains, and would close the hole it flies out of.
  std::vector<DebrisParticle> intact;
  std::vector<int> index;  // of each intact one in `particles`
  for (std::size_t i = 0; i < particles.size(); ++i)
    if (particles[i].damage < 1.0) {
      intact.push_back(particles[i]);
      index.push_back(static_cast<int>(i));
    }
  if (intact.empty()) return out;
  const DebrisOptions link;
  const std::vector<Clump> clumps = findClumps(intact, link);
  std::vector<DebrisParticle> kept;
  for (int i : clumps.front().members) {
    if (proper) proper->push_back(index[static_cast<std::size_t>(i)]);
    kept.push_back(intact[static_cast<std::size_t>(i)]);
    if (o.mirror) {
      kept.push_back(kept.back());
      kept.back().x = mirrored(kept.back().x, o);
    }
  }
  // Each covers a disc of `reach` times its radius: every point of a triangle of sides up to
  // L lies within L / sqrt(3) of a corner, so three mutually linked particles (sides up to
  // link (r_i + r_j)) leave no gap between them.
  const double reach = 2 * link.link / std::sqrt(3.0);
  std::vector<Vec3> centres;
  std::vector<double> radius;
  for (const DebrisParticle& p : kept) {
    centres.push_back(p.x);
    radius.push_back(p.radius);
  }
  setFrame(centres, o, out);
  const double r_max = *std::max_element(radius.begin(), radius.end());
  out.front += r_max;  // a particle's material reaches a radius beyond its centre
  out.rear -= r_max;
  out.u_min = out.v_min = 1e300;
  out.u_max = out.v_max = -1e300;
  for (const DebrisParticle& p : kept) {
    const Eigen::Vector2d q = out.inPlane(p.x);
    out.u_min = std::min(out.u_min, q.x() - reach * p.radius);
    out.u_max = std::max(out.u_max, q.x() + reach * p.radius);
    out.v_min = std::min(out.v_min, q.y() - reach * p.radius);
    out.v_max = std::max(out.v_max, q.y() + reach * p.radius);
  }
  // A quarter of the fine particles' spacing (twice the radius), as for tets.
  auto p10 = radius.begin() + static_cast<std::ptrdiff_t>(radius.size() / 10);
  std::nth_element(radius.begin(), p10, radius.end());
  Raster r = rasterOver(out, o.cell_size > 0 ? o.cell_size : 0.5 * *p10, o);
  for (const DebrisParticle& p : kept) r.fillDisc(out.inPlane(p.x), reach * p.radius);
  collectHoles(r, o, out);
  return out;
}

PlateHoles findHoles(const Model& model, int body, const HoleOptions& options) {
  const Body& b = model.bodies.at(static_cast<std::size_t>(body));
  std::vector<std::array<int, 4>> tets;
  for (std::size_t e = b.elem_begin; e < b.elem_end; ++e)
    if (model.elems.status[e] == ElemStatus::Live) tets.push_back(model.elems.conn[e]);
  PlateHoles out = findHoles(model.nodes.x, tets, options);
  out.plate = b.name;
  return out;
}

namespace {

std::ofstream openForWrite(const std::string& path) {
  std::ofstream out(path, std::ios::trunc);
  if (!out) throw RunError("cannot write " + path);
  return out;
}

std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}

std::string jsonString(const std::string& s) {
  std::string q = "\"";
  for (char c : s) {
    if (c == '"' || c == '\\') q += '\\';
    if (static_cast<unsigned char>(c) >= 0x20) q += c;
  }
  return q + "\"";
}

std::string point(const Vec3& p) { return "[" + num(p.x()) + ", " + num(p.y()) + ", " + num(p.z()) + "]"; }

}  // namespace

void writeHolesCsv(const std::string& path, const std::vector<PlateHoles>& plates) {
  std::ofstream out = openForWrite(path);
  out << "plate,hole,area_m2,diameter_m,centroid_x_m,centroid_y_m,centroid_z_m,on_symmetry\n";
  for (const PlateHoles& p : plates)
    for (std::size_t k = 0; k < p.holes.size(); ++k) {
      const Hole& h = p.holes[k];
      out << p.plate << ',' << k + 1 << ',' << num(h.area) << ',' << num(h.diameter) << ','
          << num(h.centroid.x()) << ',' << num(h.centroid.y()) << ',' << num(h.centroid.z())
          << ',' << (h.on_symmetry ? 1 : 0) << '\n';
    }
  if (!out) throw RunError("cannot write " + path);
}

void writeHolesJson(const std::string& path, const std::vector<PlateHoles>& plates,
                    const std::string& field, double time) {
  std::ofstream out = openForWrite(path);
  out << "{\n  \"field\": " << jsonString(field) << ", \"time_s\": " << num(time)
      << ",\n  \"plates\": [";
  for (std::size_t i = 0; i < plates.size(); ++i) {
    const PlateHoles& p = plates[i];
    out << (i ? "," : "") << "\n    {\"name\": " << jsonString(p.plate)
        << ", \"count\": " << p.holes.size() << ", \"cell_size_m\": " << num(p.cell_size)
        << ", \"normal\": " << point(p.normal) << ", \"holes\": [";
    for (std::size_t k = 0; k < p.holes.size(); ++k) {
      const Hole& h = p.holes[k];
      out << (k ? "," : "") << "\n      {\"area_m2\": " << num(h.area)
          << ", \"diameter_m\": " << num(h.diameter) << ", \"centroid_m\": " << point(h.centroid)
          << ", \"on_symmetry\": " << (h.on_symmetry ? "true" : "false") << ",\n       \"outline_m\": [";
      for (std::size_t q = 0; q < h.outline.size(); ++q) out << (q ? ", " : "") << point(h.outline[q]);
      out << "]}";
    }
    out << (p.holes.empty() ? "]}" : "\n    ]}");
  }
  out << "\n  ]\n}\n";
  if (!out) throw RunError("cannot write " + path);
}

}  // namespace fesph
