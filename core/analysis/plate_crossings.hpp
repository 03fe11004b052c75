// SPDX-License-Identifier: MIT
// Residual velocity after each plate of a spaced-plate target, the one definition used by the
// run summary, residual_velocities.csv and the report, taken for each projectile of a scene:
//
//   v_k = speed of the projectile's largest intact piece (fragments.hpp) at the first instant
//         its leading node (of a projectile made of particles: its leading particle) reaches
//         the measuring plane of plate k: the plane parallel to the
//         plate at the clear gap g behind its rear face. With equal gaps that plane is the
//         front face of plate k+1, so v_k is the speed at the end of the free flight after
//         plate k, just before the next impact; the last plate gets a virtual next plate at
//         the same gap. g = the smallest clear gap between consecutive plates, or, for a
//         single plate, the projectile's length.
//
// Beside it, at the same instant, what of the projectile got through plate k: the mass and the
// mass-weighted velocity of all its material (the live nodes' lumped masses and the particles
// born from its elements, or the particles it is made of) deeper than the plate's rear face.
// The intact piece says how fast the projectile goes on; this says how much momentum the
// plate took from the projectile's mass.
// When the projectile breaks up the two differ: its converted nose and debris travel slower
// than its intact rear.
//
// In a half model both are the full projectile's: the mirrored half cancels the velocity
// normal to the symmetry plane (wholeVelocity, model_build.hpp), which the half alone has
// wherever the impact pushes its material away from the plane.
#pragma once

#include "core/analysis/fragments.hpp"
#include "core/common/types.hpp"
#include "core/scene/scene.hpp"
#include "core/state/model.hpp"

#include <limits>
#include <string>
#include <vector>

namespace fesph {

struct PlateCrossing {
  int body = -1;
  std::string name;
  Vec3 normal = Vec3::UnitZ();  ///< unit normal of the front face, towards the projectile
  Vec3 front = Vec3::Zero();    ///< a point of the front face, m
  double thickness = 0;         ///< m
  double measure_depth = 0;     ///< depth of the measuring plane behind the front face, m
  // Filled in as the run goes:
  double t_contact = -1;        ///< s, the leading node reached the front face (-1: not yet)
  double t_measured = -1;       ///< s, v_k was taken (-1: not yet)
  Vec3 velocity = Vec3::Zero(); ///< v_k as a vector, m/s
  double speed = 0;             ///< |v_k|, m/s
  double mass_fraction = 0;     ///< the piece's mass over the projectile's initial mass
  /// All projectile material past the rear face when v_k was taken, m/s, and its mass over the
  /// projectile's initial mass; NaN where unknown (a run continued from a format-3 checkpoint).
  Vec3 through_velocity = Vec3::Constant(std::numeric_limits<double>::quiet_NaN());
  double through_mass_fraction = std::numeric_limits<double>::quiet_NaN();
};

/// Largest depth behind the front face of `p` over a piece's nodes and particles (positive:
/// behind), m; -infinity for an empty piece.
double leadingDepth(const Model& model, const PlateCrossing& p, const Piece& piece);

/// Mass (kg) and mass-weighted mean velocity (m/s) of the material of `body` (live nodes with
/// mass, and particles of that body) lying deeper than `depth` behind the front face of `p`.
struct MaterialPast {
  double mass = 0;
  Vec3 velocity = Vec3::Zero();
};
MaterialPast materialPast(const Model& model, const PlateCrossing& p, int body, double depth);

/// Where the material of `body` is along a spaced-plate target: before the first plate, in
/// each plate, in each gap, beyond the last. Depths are measured along the first plate's
/// normal (the plates are parallel); the plates in the order the projectile meets them.
struct MaterialRegion {
  std::string name;       ///< "before plate_1", "in plate_1", "plate_1 to plate_2", "beyond plate_4"
  MaterialPast nodes;     ///< its live nodes (lumped masses) in the region
  MaterialPast particles; ///< its particles in the region
  /// The particles' mass-weighted mean distance from the line through the first plate's front
  /// point along its normal (the shot line of a normal impact), m.
  double particle_offset = 0;
};
std::vector<MaterialRegion> materialByRegion(const Model& model,
                                             const std::vector<PlateCrossing>& plates, int body);

class PlateCrossings {
 public:
  /// The plates of `scene` (bodies with a plate shape, projectiles left out) in the order
  /// projectile `body` meets them (along its initial velocity). A body that is no projectile,
  /// or no plate: nothing is tracked.
  PlateCrossings(const Scene& scene, const Model& model, int body);
  /// Continue a tracking saved with a checkpoint: `plates()` and `projectile()` as they were,
  /// and the projectile's name.
  PlateCrossings(std::vector<PlateCrossing> plates, int projectile, std::string projectile_name);
  /// Look at the model after a step; cheap until the projectile nears a measuring plane.
  void update(const Model& model);
  const std::vector<PlateCrossing>& plates() const { return plates_; }
  int projectile() const { return projectile_; }
  const std::string& projectileName() const { return projectile_name_; }
  /// At the start, every plate lay behind the projectile along its velocity: it moves away
  /// from the target (a velocity's sign typed wrong, as a rule), and no plate will be crossed.
  bool headsAway() const { return heads_away_; }
  /// There are plates and the projectile has reached none of them (yet).
  bool reachedNone() const;
  /// Its rows of residual_velocities.csv (writeCrossingsCsv): one per plate, empty fields
  /// where nothing was measured, the last column naming the projectile.
  std::string csvRows() const;

 private:
  std::vector<PlateCrossing> plates_;
  int projectile_ = -1;
  std::string projectile_name_;
  bool heads_away_ = false;
  std::size_t next_ = 0;  ///< the first plate not measured yet
};

/// One tracking per projectile of `scene`, in the order of its bodies: each projectile's v_k
/// at the plates along its own flight.
std::vector<PlateCrossings> allPlateCrossings(const Scene& scene, const Model& model);

/// residual_velocities.csv: a header, then each tracking's rows (csvRows), projectile after
/// projectile. Replaces the file whole; throws RunError naming it if it cannot be written.
void writeCrossingsCsv(const std::string& path, const std::vector<PlateCrossings>& crossings);

}  // namespace fesph
