// SPDX-License-Identifier: MIT
#include "core/analysis/plate_crossings.hpp"

#include "core/analysis/fragments.hpp"
#include "core/io/replace_file.hpp"
#include "core/state/model_build.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace fesph {

double leadingDepth(const Model& model, const PlateCrossing& p, const Piece& piece) {
  double depth = -std::numeric_limits<double>::infinity();
  for (int a : piece.nodes) depth = std::max(depth, -(model.nodes.x[a] - p.front).dot(p.normal));
  for (int i : piece.particles)
    depth = std::max(depth, -(model.particles.x[i] - p.front).dot(p.normal));
  return depth;
}

namespace {

// The same over the live (massive) nodes of `body`, or the particles of a body made of them;
// -infinity when it has none. (The particles an element body's conversion makes are no part
// of its intact pieces, so they do not count.)
double bodyLeadingDepth(const Model& model, const PlateCrossing& p, int body) {
  const Body& b = model.bodies[body];
  double depth = -std::numeric_limits<double>::infinity();
  for (std::size_t a = b.node_begin; a < b.node_end; ++a)
    if (model.nodes.m[a] > 0) depth = std::max(depth, -(model.nodes.x[a] - p.front).dot(p.normal));
  if (b.discretisation == Discretisation::Sph)
    for (std::size_t i = 0; i < model.particles.size(); ++i)
      if (model.particles.body[i] == body)
        depth = std::max(depth, -(model.particles.x[i] - p.front).dot(p.normal));
  return depth;
}

}  // namespace

MaterialPast materialPast(const Model& model, const PlateCrossing& p, int body, double depth) {
  MaterialPast out;
  Vec3 momentum = Vec3::Zero();
  auto add = [&](const Vec3& x, const Vec3& v, double m) {
    if (m > 0 && -(x - p.front).dot(p.normal) > depth) out.mass += m, momentum += m * v;
  };
  const Body& b = model.bodies[body];
  for (std::size_t a = b.node_begin; a < b.node_end; ++a)
    add(model.nodes.x[a], model.nodes.v[a], model.nodes.m[a]);
  const Particles& pa = model.particles;
  for (std::size_t i = 0; i < pa.size(); ++i)
    if (pa.body[i] == body) add(pa.x[i], pa.v[i], pa.m[i]);
  if (out.mass > 0) out.velocity = wholeBodyVelocity(model, body, momentum / out.mass);
  return out;
}

std::vector<MaterialRegion> materialByRegion(const Model& model,
                                             const std::vector<PlateCrossing>& plates, int body) {
  std::vector<MaterialRegion> regions;
  if (plates.empty() || body < 0) return regions;
  const Vec3 n = plates[0].normal, o = plates[0].front;
  const auto depth = [&](const Vec3& x) { return -(x - o).dot(n); };
  // Region 2k + 1 is plate k, 2k its gap before (0: before the first), 2 N beyond the last.
  const std::size_t np = plates.size();
  regions.resize(2 * np + 1);
  for (std::size_t k = 0; k < np; ++k) {
    regions[2 * k + 1].name = "in " + plates[k].name;
    regions[2 * k + 2].name = k + 1 < np ? plates[k].name + " to " + plates[k + 1].name
                                         : "beyond " + plates[k].name;
  }
  regions[0].name = "before " + plates[0].name;
  const auto regionOf = [&](const Vec3& x) {
    const double d = depth(x);
    std::size_t r = 0;
    for (std::size_t k = 0; k < np; ++k) {
      const double front = depth(plates[k].front);
      if (d >= front) r = 2 * k + 1;
      if (d > front + plates[k].thickness) r = 2 * k + 2;
    }
    return r;
  };
  std::vector<Vec3> p_node(regions.size(), Vec3::Zero()), p_particle(regions.size(), Vec3::Zero());
  const Body& b = model.bodies[body];
  for (std::size_t a = b.node_begin; a < b.node_end; ++a) {
    const double m = model.nodes.m[a];
    if (!(m > 0)) continue;
    const std::size_t r = regionOf(model.nodes.x[a]);
    regions[r].nodes.mass += m;
    p_node[r] += m * model.nodes.v[a];
  }
  const Particles& pa = model.particles;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    if (pa.body[i] != body) continue;
    const std::size_t r = regionOf(pa.x[i]);
    const Vec3 off = (pa.x[i] - o) - (pa.x[i] - o).dot(n) * n;
    regions[r].particles.mass += pa.m[i];
    p_particle[r] += pa.m[i] * pa.v[i];
    regions[r].particle_offset += pa.m[i] * off.norm();
  }
  const unsigned planes = planesCutting(model, body);  // the full body's (wholeVelocity)
  for (std::size_t r = 0; r < regions.size(); ++r) {
    MaterialRegion& g = regions[r];
    if (g.nodes.mass > 0) g.nodes.velocity = alongPlanes(p_node[r] / g.nodes.mass, planes);
    if (g.particles.mass > 0) {
      g.particles.velocity = alongPlanes(p_particle[r] / g.particles.mass, planes);
      g.particle_offset /= g.particles.mass;
    }
  }
  return regions;
}

PlateCrossings::PlateCrossings(const Scene& scene, const Model& model, int body) {
  if (body < 0 || static_cast<std::size_t>(body) >= model.bodies.size() ||
      !model.bodies[body].is_projectile)
    return;
  projectile_ = body;
  const Body& pb = model.bodies[projectile_];
  projectile_name_ = pb.name;
  // Its nodes, or the particles of a body made of them (no others exist at the start).
  std::vector<Vec3> points;
  Vec3 v0 = Vec3::Zero(), c0 = Vec3::Zero();
  double m0 = 0, zmin = std::numeric_limits<double>::infinity(), zmax = -zmin;
  const auto add = [&](const Vec3& x, const Vec3& v, double m) {
    v0 += m * v;
    c0 += m * x;
    m0 += m;
    points.push_back(x);
  };
  for (std::size_t a = pb.node_begin; a < pb.node_end; ++a)
    add(model.nodes.x[a], model.nodes.v[a], model.nodes.m[a]);
  for (std::size_t i = 0; i < model.particles.size(); ++i)
    if (model.particles.body[i] == projectile_)
      add(model.particles.x[i], model.particles.v[i], model.particles.m[i]);
  if (!(m0 > 0) || v0.norm() == 0) return;
  const Vec3 dir = v0.normalized();
  c0 /= m0;
  for (const Vec3& x : points) {
    zmin = std::min(zmin, x.dot(dir));
    zmax = std::max(zmax, x.dot(dir));
  }
  const double length = zmax - zmin;

  for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
    const auto* spec = std::get_if<PlateSpec>(&scene.bodies[b].shape);
    if (!spec || model.bodies[b].is_projectile) continue;  // a projectile is no target
    PlateCrossing p;
    p.body = static_cast<int>(b);
    p.name = scene.bodies[b].name;
    p.normal = scene.bodies[b].placement.rotation * Vec3::UnitZ();
    p.front = scene.bodies[b].placement.translation;
    p.thickness = spec->thickness;
    plates_.push_back(p);
  }
  std::stable_sort(plates_.begin(), plates_.end(), [&](const auto& a, const auto& b) {
    return (a.front - c0).dot(dir) < (b.front - c0).dot(dir);
  });
  heads_away_ = !plates_.empty() && (plates_.back().front - c0).dot(dir) < 0;
  // Clear gap between consecutive plates, measured along the normal of the first one.
  double gap = std::numeric_limits<double>::infinity();
  for (std::size_t k = 0; k + 1 < plates_.size(); ++k) {
    const PlateCrossing& p = plates_[k];
    gap = std::min(gap, -(plates_[k + 1].front - p.front).dot(p.normal) - p.thickness);
  }
  if (plates_.size() < 2) gap = length;
  for (PlateCrossing& p : plates_) p.measure_depth = p.thickness + gap;
}

PlateCrossings::PlateCrossings(std::vector<PlateCrossing> plates, int projectile,
                               std::string projectile_name)
    : plates_(std::move(plates)), projectile_(projectile),
      projectile_name_(std::move(projectile_name)) {
  while (next_ < plates_.size() && plates_[next_].t_measured >= 0) ++next_;  // measured in order
}

bool PlateCrossings::reachedNone() const {
  if (plates_.empty()) return false;
  for (const PlateCrossing& p : plates_)
    if (p.t_contact >= 0) return false;
  return true;
}

void PlateCrossings::update(const Model& model) {
  if (projectile_ < 0 || next_ >= plates_.size()) return;
  for (PlateCrossing& p : plates_)
    if (p.t_contact < 0 && bodyLeadingDepth(model, p, projectile_) >= 0) p.t_contact = model.time;
  // Any live node past the measuring plane: is it the largest piece's?
  while (next_ < plates_.size()) {
    PlateCrossing& p = plates_[next_];
    if (bodyLeadingDepth(model, p, projectile_) < p.measure_depth) return;
    const std::vector<Piece> pieces = bodyPieces(model, projectile_);
    if (pieces.empty() || leadingDepth(model, p, pieces.front()) < p.measure_depth) return;
    p.t_measured = model.time;
    p.velocity = pieces.front().velocity;
    p.speed = p.velocity.norm();
    const double m0 = bodyInitialMass(model, projectile_);
    p.mass_fraction = m0 > 0 ? pieces.front().mass / m0 : 0.0;
    const MaterialPast through = materialPast(model, p, projectile_, p.thickness);
    p.through_velocity = through.velocity;
    p.through_mass_fraction = m0 > 0 ? through.mass / m0 : 0.0;
    ++next_;
  }
}

std::string PlateCrossings::csvRows() const {
  std::string text;
  for (std::size_t k = 0; k < plates_.size(); ++k) {
    const PlateCrossing& p = plates_[k];
    char row[512];
    if (p.t_measured >= 0 && !std::isfinite(p.through_mass_fraction))
      std::snprintf(row, sizeof row, "%zu,%s,%.9g,%.9g,%.6g,%.6g,%.6g,%.6g,%.6g,,", k + 1,
                    p.name.c_str(), p.t_contact, p.t_measured, p.speed, p.velocity.x(),
                    p.velocity.y(), p.velocity.z(), p.mass_fraction);
    else if (p.t_measured >= 0)
      std::snprintf(row, sizeof row, "%zu,%s,%.9g,%.9g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g",
                    k + 1, p.name.c_str(), p.t_contact, p.t_measured, p.speed, p.velocity.x(),
                    p.velocity.y(), p.velocity.z(), p.mass_fraction, p.through_velocity.norm(),
                    p.through_mass_fraction);
    else if (p.t_contact >= 0)
      std::snprintf(row, sizeof row, "%zu,%s,%.9g,,,,,,,,", k + 1, p.name.c_str(), p.t_contact);
    else
      std::snprintf(row, sizeof row, "%zu,%s,,,,,,,,,", k + 1, p.name.c_str());
    text += row;
    text += "," + projectile_name_ + "\n";
  }
  return text;
}

std::vector<PlateCrossings> allPlateCrossings(const Scene& scene, const Model& model) {
  std::vector<PlateCrossings> all;
  for (std::size_t b = 0; b < model.bodies.size(); ++b)
    if (model.bodies[b].is_projectile) all.emplace_back(scene, model, static_cast<int>(b));
  return all;
}

void writeCrossingsCsv(const std::string& path, const std::vector<PlateCrossings>& crossings) {
  std::string text =
      "plate,name,t_contact_s,t_measured_s,residual_velocity_m_s,vx_m_s,vy_m_s,vz_m_s,"
      "mass_fraction,through_velocity_m_s,through_mass_fraction,projectile\n";
  for (const PlateCrossings& c : crossings) text += c.csvRows();
  // rewritten at every output: through a temporary, so that a run killed mid-write keeps the
  // last complete table, and a write that fails stops the run instead of losing it silently
  replaceFile(path, text);
}

}  // namespace fesph
