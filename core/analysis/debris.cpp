// SPDX-License-Identifier: MIT
#include "core/analysis/debris.hpp"

#include "core/common/union_find.hpp"
#include "core/io/replace_file.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>

namespace fesph {

namespace {

using Cell = std::array<long long, 3>;

Cell cellOf(const Vec3& x, double size) {
  return {static_cast<long long>(std::floor(x.x() / size)),
          static_cast<long long>(std::floor(x.y() / size)),
          static_cast<long long>(std::floor(x.z() / size))};
}

// Joins every linked pair: particles sorted by grid cell (edge = the longest link), each one
// checked against the particles of its own and the 26 neighbouring cells.
void linkParticles(const std::vector<DebrisParticle>& p, double link, UnionFind& sets) {
  double r_max = 0;
  for (const DebrisParticle& q : p) r_max = std::max(r_max, q.radius);
  if (!(r_max > 0)) return;
  const double size = 2 * link * r_max;
  std::vector<std::pair<Cell, int>> sorted(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) sorted[i] = {cellOf(p[i].x, size), static_cast<int>(i)};
  std::sort(sorted.begin(), sorted.end());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const Cell c = cellOf(p[i].x, size);
    for (long long dx = -1; dx <= 1; ++dx)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dz = -1; dz <= 1; ++dz) {
          const Cell n = {c[0] + dx, c[1] + dy, c[2] + dz};
          auto at = std::lower_bound(sorted.begin(), sorted.end(), std::make_pair(n, -1));
          for (; at != sorted.end() && at->first == n; ++at) {
            const std::size_t j = static_cast<std::size_t>(at->second);
            if (j <= i || p[j].body != p[i].body) continue;
            const double reach = link * (p[i].radius + p[j].radius);
            if ((p[i].x - p[j].x).squaredNorm() <= reach * reach)
              sets.join(static_cast<int>(j), static_cast<int>(i));
          }
        }
  }
}

}  // namespace

std::vector<Clump> findClumps(const std::vector<DebrisParticle>& particles,
                              const DebrisOptions& options) {
  const std::size_t n = particles.size();
  UnionFind sets(n);
  linkParticles(particles, options.link, sets);

  // Clumps numbered in the order of their first particle; sums first, then the moments.
  std::vector<int> clump_of(n, -1), index_of_root(n, -1);
  std::vector<Clump> clumps;
  for (std::size_t i = 0; i < n; ++i) {
    const int root = sets.find(static_cast<int>(i));
    if (index_of_root[root] < 0) {
      index_of_root[root] = static_cast<int>(clumps.size());
      clumps.emplace_back();
      clumps.back().body = particles[i].body;
    }
    clump_of[i] = index_of_root[root];
    const DebrisParticle& q = particles[i];
    Clump& c = clumps[clump_of[i]];
    ++c.particles;
    c.members.push_back(static_cast<int>(i));
    c.mass += q.mass;
    c.centroid += q.mass * q.x;
    c.velocity += q.mass * q.v;
    c.damage += q.mass * q.damage;
    if (options.half && std::abs(q.x.y()) <= options.link * q.radius) c.on_plane = true;
  }
  for (Clump& c : clumps) {
    if (c.mass > 0) c.centroid /= c.mass, c.velocity /= c.mass, c.damage /= c.mass;
    c.full_mass = c.on_plane ? 2 * c.mass : c.mass;
    // A clump on the plane with its mirror image is one clump of the full model: its centre
    // lies on the plane and moves along it; its size and spread below then count the
    // distance and the sideways speed of its half from there, as its mirror half's.
    if (c.on_plane) c.centroid.y() = 0, c.velocity.y() = 0;
  }
  for (std::size_t i = 0; i < n; ++i) {
    const DebrisParticle& q = particles[i];
    Clump& c = clumps[clump_of[i]];
    c.size += q.mass * (q.x - c.centroid).squaredNorm();
    c.spread += q.mass * (q.v - c.velocity).squaredNorm();
  }
  for (Clump& c : clumps)
    if (c.mass > 0) c.size = std::sqrt(c.size / c.mass), c.spread = std::sqrt(c.spread / c.mass);
  std::stable_sort(clumps.begin(), clumps.end(),
                   [](const Clump& a, const Clump& b) { return a.mass > b.mass; });
  return clumps;
}

Strike predictStrike(const Clump& clump, const std::vector<TargetPlate>& plates) {
  Strike best;
  best.after = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k < plates.size(); ++k) {
    const TargetPlate& t = plates[k];
    if (t.body == clump.body) continue;
    const double height = (clump.centroid - t.centre).dot(t.normal) - t.front;  // in front: > 0
    const double closing = -clump.velocity.dot(t.normal);
    if (height < 0 || !(closing > 0)) continue;
    const double after = height / closing;
    const Vec3 point = clump.centroid + after * clump.velocity;
    const Vec3 d = point - t.centre;
    if (std::abs(d.dot(t.u)) > t.half_u || std::abs(d.dot(t.v)) > t.half_v) continue;
    if (after < best.after) best = {static_cast<int>(k), after, point, closing};
  }
  if (best.plate < 0) best.after = 0;
  return best;
}

DebrisSummary writeDebrisCsv(const std::string& path, double time, const std::vector<Clump>& clumps,
                    const std::vector<TargetPlate>& plates,
                    const std::vector<std::string>& body_names, std::size_t min_particles) {
  std::string text =
      "time_s,body,clump,particles,mass_kg,full_mass_kg,speed_m_s,vx_m_s,vy_m_s,vz_m_s,x_m,y_m,"
      "z_m,damage,size_m,spread_m_s,on_symmetry,strikes,strike_after_s,strike_time_s,"
      "strike_x_m,strike_y_m,strike_z_m,strike_normal_speed_m_s\n";
  std::vector<int> rank(body_names.size() + 1, 0);
  DebrisSummary summary;
  for (const Clump& c : clumps) {
    if (c.particles < min_particles) continue;
    ++summary.clumps;
    const std::size_t b = c.body >= 0 && static_cast<std::size_t>(c.body) < body_names.size()
                              ? static_cast<std::size_t>(c.body)
                              : body_names.size();
    const std::string body =
        b < body_names.size() ? body_names[b] : "body" + std::to_string(c.body);
    char row[768];
    int w = std::snprintf(
        row, sizeof row, "%.9g,%s,%d,%zu,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.4f,%.4g,%.4g,%d,",
        time, body.c_str(), ++rank[b], c.particles, c.mass, c.full_mass, c.velocity.norm(),
        c.velocity.x(), c.velocity.y(), c.velocity.z(), c.centroid.x(), c.centroid.y(),
        c.centroid.z(), c.damage, c.size, c.spread, c.on_plane ? 1 : 0);
    w = std::clamp(w, 0, static_cast<int>(sizeof row) - 1);
    const Strike s = predictStrike(c, plates);
    if (s.plate >= 0) {
      ++summary.strikes;
      std::snprintf(row + w, sizeof row - static_cast<std::size_t>(w),
                    "%s,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n", plates[s.plate].name.c_str(), s.after,
                    time + s.after, s.point.x(), s.point.y(), s.point.z(), s.normal_speed);
    } else {
      std::snprintf(row + w, sizeof row - static_cast<std::size_t>(w), ",,,,,,\n");
    }
    text += row;
  }
  replaceFile(path, text);
  return summary;
}

}  // namespace fesph
