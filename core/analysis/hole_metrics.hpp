// SPDX-License-Identifier: MIT
// Through-holes of a perforated plate, from geometry (not pixels): the live tetrahedra (or a
// plate made of particles, its particles as discs) are projected onto the plate's mid-plane and
// rasterised; holes are the enclosed empty regions.
#pragma once

#include "core/common/types.hpp"
#include "core/state/model.hpp"

#include <array>
#include <string>
#include <vector>

namespace fesph {

struct DebrisParticle;

struct HoleOptions {
  /// Raster cell edge, m. 0: a quarter of the 10th-percentile tet edge length (the fine mesh),
  /// or of the 10th-percentile particle spacing (twice the radius).
  double cell_size = 0;
  /// The raster never exceeds this many cells; the cell grows to fit.
  std::size_t max_cells = 16'000'000;
  /// Openings smaller than this are ignored, m^2 (full plate). 0: four raster cells.
  double min_area = 0;
  /// Half model: mirror the plate on this plane before looking for holes, so a hole cut by
  /// the symmetry plane is found whole and every value is a full-plate value.
  bool mirror = false;
  int symmetry_axis = 1;            ///< 0, 1, 2 = x, y, z
  double symmetry_position = 0.0;   ///< m
  /// Plate normal; zero: the direction of smallest extent of the plate's nodes (PCA).
  Vec3 normal = Vec3::Zero();
};

struct Hole {
  double area = 0;             ///< full plate, m^2
  double diameter = 0;         ///< equivalent diameter sqrt(4 area / pi), m
  Vec3 centroid = Vec3::Zero();  ///< on the mid-plane, m
  /// Closed outline on the mid-plane (last point joins the first), m: the hole's outer edge
  /// (islands inside it), following the raster cells with the staircase corners cut.
  std::vector<Vec3> outline;
  bool on_symmetry = false;    ///< crosses the symmetry plane (mirrored half models)
};

struct PlateHoles {
  std::string plate;                 ///< body name
  Vec3 origin = Vec3::Zero();        ///< a point of the mid-plane, m
  Vec3 normal = Vec3::UnitZ();       ///< unit; points to the front (+z side unless given)
  Vec3 u = Vec3::UnitX(), v = Vec3::UnitY();  ///< in-plane axes; v is global y projected
  double front = 0, rear = 0;        ///< normal coordinates of the front and rear extremes, m
  /// In-plane extent of the plate proper (its largest piece; mirrored for half models): u and
  /// v coordinates from the origin, m. Loose pieces of the plate do not widen it.
  double u_min = 0, u_max = 0, v_min = 0, v_max = 0;
  double cell_size = 0;              ///< raster cell edge used, m
  std::vector<Hole> holes;           ///< largest first

  /// The u and v coordinates of `p` from `origin` (p projected on the mid-plane), m.
  Eigen::Vector2d inPlane(const Vec3& p) const {
    return {(p - origin).dot(u), (p - origin).dot(v)};
  }
  /// Middle of the plate proper's extent, on the plane through `origin`, m.
  Vec3 extentCentre() const {
    return origin + 0.5 * (u_min + u_max) * u + 0.5 * (v_min + v_max) * v;
  }
  double halfU() const { return 0.5 * (u_max - u_min); }  ///< half the extent along u, m
  double halfV() const { return 0.5 * (v_max - v_min); }  ///< half the extent along v, m
};

/// Holes of the plate made of the tetrahedra `tets` over the points `x` (every tet counts as
/// live). Only the largest node-connected piece counts as the plate: plugs and fragments that
/// came loose do not close a hole even when they still lie in front of it.
PlateHoles findHoles(const std::vector<Vec3>& x, const std::vector<std::array<int, 4>>& tets,
                     const HoleOptions& options = {});

/// Holes of a plate made of particles (DebrisParticle: position, mass, radius, damage). The
/// plate proper is the largest clump of its unfailed particles (damage < 1; linked as
/// debris.hpp's DebrisOptions::link says: |x_i - x_j| <= 1.5 (r_i + r_j)): failed particles,
/// plugs and fragments that came loose do not close a hole. Each particle of it covers a disc
/// of sqrt(3) its radius on the mid-plane, which leaves no gap within a triangle of linked
/// particles. A hole's edge is resolved to about a particle spacing (twice the radius), holes
/// coming out smaller by about 0.8 of it in diameter; front and rear are the extreme centres'
/// plus a radius. `proper` (if given) receives the indices
/// of the plate proper's particles, ascending.
PlateHoles findParticleHoles(const std::vector<DebrisParticle>& particles,
                             const HoleOptions& options = {}, std::vector<int>* proper = nullptr);

/// Holes of the live elements of body `body` of `model`, at the current positions.
PlateHoles findHoles(const Model& model, int body, const HoleOptions& options = {});

/// One row per hole: plate, hole, area_m2, diameter_m, centroid_x/y/z_m, on_symmetry.
/// Plates without holes get no row. Throws RunError when the file cannot be written.
void writeHolesCsv(const std::string& path, const std::vector<PlateHoles>& plates);

/// {"field", "time_s", "plates": [{"name", "count", "cell_size_m", "holes": [{area_m2,
/// diameter_m, centroid_m, on_symmetry, outline_m: [[x,y,z], ...]}]}]}: `field` and `time` say
/// what the images drawn with the holes show. Throws RunError when it cannot be written.
void writeHolesJson(const std::string& path, const std::vector<PlateHoles>& plates,
                    const std::string& field, double time);

}  // namespace fesph
