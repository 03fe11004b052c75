// SPDX-License-Identifier: MIT
// Debris behind a plate: the free particles (not tied to an element face) grouped into clumps,
// each with its mass, velocity and damage, and where it would strike a plate flying on in a
// straight line. Which fragments of plate 1 can punch a hole in plate 2 is read from this.
#pragma once

#include "core/common/types.hpp"

#include <string>
#include <vector>

namespace fesph {

struct DebrisParticle {
  Vec3 x = Vec3::Zero();  ///< position, m
  Vec3 v = Vec3::Zero();  ///< velocity, m/s
  double mass = 0;        ///< kg
  double radius = 0;      ///< m
  double damage = 0;      ///< Johnson-Cook damage, 0..1
  int body = -1;          ///< the body whose element it was born from
};

struct DebrisOptions {
  /// Two particles of a body are linked when |x_i - x_j| <= link (r_i + r_j): neighbours of a
  /// particle lattice (spacing ~2 r) are linked, particles a spacing apart are not.
  double link = 1.5;
  /// Half model cut on y = 0: a clump that reaches the plane (a particle within link r_i of
  /// it) is half of a clump of the full model.
  bool half = false;
};

struct Clump {
  int body = -1;
  std::size_t particles = 0;
  double mass = 0;                  ///< kg, in the model (see full_mass)
  double full_mass = 0;             ///< kg, in the full model: twice `mass` if on_plane
  /// Mass-weighted centre and velocity, m and m/s; of the full clump, with its mirror image,
  /// if on_plane (on the plane, along it), and likewise its size and spread.
  Vec3 centroid = Vec3::Zero();
  Vec3 velocity = Vec3::Zero();
  double damage = 0;                ///< mass-weighted mean
  double size = 0;                  ///< rms distance of its particles from the centroid, m
  double spread = 0;                ///< rms speed of its particles relative to `velocity`, m/s
  bool on_plane = false;            ///< reaches a half model's symmetry plane
  std::vector<int> members;         ///< its particles' indices in the list clumped, ascending
};

/// Clumps of particles linked (DebrisOptions::link) within each body. Every particle belongs
/// to exactly one clump, so the masses sum to the particles' mass. Largest mass first; equal
/// masses in the order of their first particle.
std::vector<Clump> findClumps(const std::vector<DebrisParticle>& particles,
                              const DebrisOptions& options = {});

/// A plate as a target: its front face is the plane (x - centre) . normal = front, bounded
/// by |(x - centre) . u| <= half_u and |(x - centre) . v| <= half_v. The normal points to the
/// side the projectile comes from.
struct TargetPlate {
  std::string name;
  int body = -1;
  Vec3 centre = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ(), u = Vec3::UnitX(), v = Vec3::UnitY();
  double front = 0;  ///< m
  double half_u = 0, half_v = 0;  ///< m
};

struct Strike {
  int plate = -1;                ///< index into the plates; -1: strikes none
  double after = 0;              ///< flight time from the snapshot, s
  Vec3 point = Vec3::Zero();     ///< on the front face, m
  double normal_speed = 0;       ///< speed into the plate, m/s
};

/// Where a clump flying on from its centroid at its velocity first meets the front face of a
/// plate of another body, within the plate's extent: plates it is behind, moves away from or
/// passes beside are not struck.
Strike predictStrike(const Clump& clump, const std::vector<TargetPlate>& plates);

struct DebrisSummary {
  std::size_t clumps = 0;   ///< rows written: clumps of at least `min_particles` particles
  std::size_t strikes = 0;  ///< of them, those that would strike a plate
};

/// One row per clump of at least `min_particles` particles (largest first): body, clump,
/// particles, mass and full mass, speed, velocity, centroid, damage, size, spread, on_plane,
/// and the plate it would strike (name, flight time, time of arrival, point, normal speed;
/// empty when none). `time` is the snapshot's, s. Throws RunError when it cannot write.
DebrisSummary writeDebrisCsv(const std::string& path, double time, const std::vector<Clump>& clumps,
                    const std::vector<TargetPlate>& plates,
                    const std::vector<std::string>& body_names, std::size_t min_particles = 2);

}  // namespace fesph
