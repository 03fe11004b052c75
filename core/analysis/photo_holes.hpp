// SPDX-License-Identifier: MIT
// Holes in a photograph of a tested plate, and their comparison with the simulated plate:
// threshold (Otsu, or given), connected components, hole sizes on the plate's scale, and the
// intersection-over-union with the simulated hole map on the photograph's pixel grid.
#pragma once

#include "core/analysis/hole_metrics.hpp"

#include <Eigen/Dense>

#include <array>
#include <cstdint>
#include <optional>
#include <vector>

namespace fesph {

/// A grey photograph: brightness in [0, 1], row-major, row 0 at the top (as photographs are).
struct GrayImage {
  int width = 0, height = 0;
  std::vector<float> value;
  float at(int i, int j) const { return value[static_cast<std::size_t>(j) * width + i]; }
};

/// Otsu's threshold: the brightness that maximises the between-class variance of the
/// histogram (256 bins over [0, 1]). Returns the upper edge of the darker class's last bin.
double otsuThreshold(const GrayImage& image);

struct SegmentOptions {
  /// Brightness splitting holes from plate, in (0, 1); < 0: Otsu's threshold of the photograph
  /// after a 3x3 smoothing.
  double threshold = -1;
  /// Holes darker than the plate (a lit plate in front of a dark background); false: holes
  /// brighter (a plate lit from behind).
  bool dark_holes = true;
  /// Hole pixels in components smaller than this are ignored (noise, dirt). 0: 25 pixels.
  int min_area_px = 0;
};

struct PhotoHole {
  double area_px = 0;                          ///< pixels
  Eigen::Vector2d centroid_px = Eigen::Vector2d::Zero();  ///< (column, row) of pixel centres
};

/// Holes of a photograph: 4-connected components of hole-class pixels that do not touch the
/// image border (the background around the plate does).
struct PhotoSegmentation {
  int width = 0, height = 0;
  double threshold = 0;   ///< the threshold used
  bool automatic = true;  ///< Otsu's (true) or given
  std::vector<int> label;        ///< per pixel: k + 1 in holes[k], 0 outside every kept hole
  std::vector<PhotoHole> holes;    ///< largest first
};

/// Throws InputError for an empty image or a threshold outside (0, 1).
PhotoSegmentation segmentHoles(const GrayImage& image, const SegmentOptions& options = {});

/// The simulated plate seen along its normal: its through-holes (full plate) and its in-plane
/// extent, in the (u, v) coordinates of holes' frame relative to holes.origin, m.
struct SimulatedPlate {
  PlateHoles holes;
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();     ///< middle of the extent
  Eigen::Vector2d half_size = Eigen::Vector2d::Zero();  ///< half the extent along u and v
};

/// findHoles on the tets `tets` over `x`, and the extent of their (mirrored, if options.mirror)
/// nodes.
SimulatedPlate simulatedPlate(const std::vector<Vec3>& x,
                              const std::vector<std::array<int, 4>>& tets,
                              const HoleOptions& options = {});

/// findParticleHoles on a plate made of particles, and the extent of the plate proper (its
/// largest clump, mirrored if options.mirror).
SimulatedPlate simulatedParticlePlate(const std::vector<DebrisParticle>& particles,
                                      const HoleOptions& options = {});

/// Photograph pixel (column, row; pixel centres at +0.5) <-> plate coordinates, m: along the
/// frame's u and v from the plate's centre (SimulatedPlate::centre).
/// The photograph's right is +u and up is +v for a photograph of the front face (the view of
/// the front plate image); a photograph of the rear face is mirrored left-right.
struct PhotoFrame {
  double m_per_px = 0;
  Eigen::Vector2d pixel_ref = Eigen::Vector2d::Zero();  ///< a pixel position ...
  Eigen::Vector2d plate_ref = Eigen::Vector2d::Zero();  ///< ... and the plate point it shows
  bool rear = false;
  Eigen::Vector2d toPlate(const Eigen::Vector2d& px) const;
  Eigen::Vector2d toPixel(const Eigen::Vector2d& uv) const;
};

struct CompareOptions {
  double m_per_px = 0;  ///< the photograph's scale, m per pixel (> 0)
  /// Pixel (column, row) where the simulated plate's centre lies. None: the photograph's largest
  /// hole's centroid is put on the simulated plate's largest hole's (the projectile's hole, as
  /// a rule; the fragment holes, which the two sides need not share, do not pull it).
  std::optional<Eigen::Vector2d> centre_px;
  bool rear = false;  ///< the photograph shows the rear face
};

/// One hole's size on the plate.
struct HoleSize {
  double area = 0;      ///< m^2
  double diameter = 0;  ///< equivalent diameter sqrt(4 area / pi), m
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();  ///< plate coordinates (PhotoFrame), m
};

/// A photographed hole and a simulated hole that overlap on the photograph's pixel grid.
struct HolePair {
  std::size_t photo = 0, simulated = 0;  ///< indices into HoleComparison::photo and ::simulated
  double overlap = 0;  ///< area in both, m^2
  double iou = 0;      ///< the two holes' own intersection-over-union
};

struct HoleComparison {
  PhotoFrame frame;
  std::vector<HoleSize> photo, simulated;  ///< largest first
  /// Every overlapping pair, largest overlap first. A hole in no pair is on one side only: a
  /// fragment hole the simulation did not make, or one the test plate did not show.
  std::vector<HolePair> pairs;
  /// Per photograph pixel: k + 1 in simulated[k]'s outline (the later one where two overlap),
  /// 0 outside every simulated hole.
  std::vector<int> simulated_label;
  std::size_t photo_px = 0, simulated_px = 0, both_px = 0;
  double iou = 0;  ///< |photo ∩ simulated| / |photo ∪ simulated| over the pixels; 0 if both empty
  /// Share of the simulated holes' area that falls outside the photograph (not compared).
  double simulated_outside = 0;
};

/// Register the photograph on the simulated plate and compare the two hole maps on the
/// photograph's pixel grid (simulated holes: their outline polygons, filled), as a whole (iou)
/// and hole by hole (pairs). Throws InputError for a bad scale, or without centre_px when either
/// side has no hole.
HoleComparison compareHoles(const PhotoSegmentation& photo, const SimulatedPlate& plate,
                            const CompareOptions& options);

/// The other side's holes that `hole` overlaps (indices), in pair order; empty for a hole on one
/// side only. `photo_side`: `hole` indexes the photographed holes, else the simulated ones.
std::vector<std::size_t> partnersOf(const HoleComparison& c, std::size_t hole, bool photo_side);

/// Distance from a hole's centroid to the nearest centroid of the other side's holes, m;
/// infinity when the other side has none.
double nearestOther(const HoleComparison& c, std::size_t hole, bool photo_side);

/// Pixels of a `width` x `height` grid whose centre lies inside one of `polygons` (pixel
/// coordinates; each polygon closed implicitly, even-odd rule, filled one after the other):
/// k + 1 for a pixel of polygons[k] (the last to cover it), 0 outside all.
std::vector<int> fillPolygons(const std::vector<std::vector<Eigen::Vector2d>>& polygons,
                              int width, int height);

}  // namespace fesph
