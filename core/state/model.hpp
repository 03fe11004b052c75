// SPDX-License-Identifier: MIT
// The one owner of the simulation state: nodes, tetrahedra, particles, bodies, boundary
// conditions and the energy budget. Structure of arrays, double precision, SI units.
#pragma once

#include "core/common/reflection.hpp"
#include "core/common/types.hpp"
#include "core/material/material.hpp"
#include "core/solver/phase_timers.hpp"
#include "core/sph/sph_workspace.hpp"
#include "core/state/surfaces.hpp"

#include <array>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

namespace fesph {

enum class ElemStatus : std::uint8_t { Live = 0, Converted = 1, Eroded = 2 };

/// Why an element erodes or converts (core/conversion/triggers.hpp); None: it stays.
enum class Trigger : std::uint8_t { None, PlasticStrain, Damage, Safety };

/// Nodes of the tetrahedral meshes of all bodies.
struct Nodes {
  std::vector<Vec3> x;            ///< current position, m
  std::vector<Vec3> x0;           ///< reference position, m
  std::vector<Vec3> v;            ///< velocity at the last half step, m/s
  std::vector<Vec3> f;            ///< internal + external force, N
  std::vector<double> m;          ///< lumped mass, kg (0: inactive node)
  std::vector<int> body;          ///< owning body
  std::vector<std::uint8_t> fix;  ///< bit k set: velocity component k held at zero
  std::size_t size() const { return x.size(); }
  /// What an impulse (contact, tie) moves node a by per unit: 1/m, and 0 for a node held in
  /// every direction or without mass, which the impulse cannot move.
  double inverseMass(std::size_t a) const {
    return fix[a] == 0b111 || !(m[a] > 0) ? 0.0 : 1.0 / m[a];
  }
  /// v_a += dv, except in the directions node a is held in.
  void addVelocity(std::size_t a, Vec3 dv) {
    for (int k = 0; k < 3; ++k)
      if (fix[a] & (1u << k)) dv[k] = 0.0;
    v[a] += dv;
  }
};

/// Linear tetrahedra of all bodies.
struct Elements {
  std::vector<std::array<int, 4>> conn;  ///< node ids, positively oriented
  std::vector<int> body;                 ///< owning body
  std::vector<int> material;             ///< index into Model::materials
  std::vector<double> V0;                ///< reference volume, m^3
  std::vector<double> V;                 ///< current volume, m^3
  std::vector<double> dV;                ///< volume change over the last interval, m^3
  std::vector<double> rho;               ///< current density, kg/m^3
  std::vector<double> q;                 ///< bulk viscosity pressure, Pa
  std::vector<double> div_v;             ///< volumetric strain rate tr(D) of the last interval, 1/s
  std::vector<double> dt;                ///< stable time step estimate, s
  std::vector<double> len, len0;         ///< smallest altitude now and at the first step, m
  std::vector<PointState> state;         ///< stress and history variables
  std::vector<ElemStatus> status;
  /// Scratch, not in the checkpoint: each element's flow stress factors from its last step,
  /// sized and keyed by the element pass (material.hpp).
  std::vector<YieldCache> yield_cache;
  /// Scratch, not in the checkpoint: each element's trigger as the element pass of step
  /// `trigger_step` evaluated it, where the element's state was in cache. Nothing changes an
  /// element between that pass and the next step's conversions, which read these
  /// (triggeredElements) instead of every element's state again.
  std::vector<Trigger> trigger;
  long trigger_step = -1;
  std::size_t size() const { return conn.size(); }
};

/// A particle's tie to an exterior face of a live element (the paper's coupling, eqs. 6-12).
struct Tie {
  std::array<int, 3> face = {-1, -1, -1};  ///< node ids of the face; face[0] < 0: not tied
  Vec3 bary = Vec3::Zero();                ///< barycentric coordinates of the tie point
  bool active() const { return face[0] >= 0; }
};

/// SPH particles: converted elements, or bodies made of particles from the start.
struct Particles {
  std::vector<Vec3> x;            ///< position, m
  std::vector<Vec3> v;            ///< velocity at the last half step, m/s
  std::vector<Vec3> f;            ///< force, N
  std::vector<double> m;          ///< mass, kg
  std::vector<double> V;          ///< current volume, m^3
  std::vector<double> rho;        ///< current density, kg/m^3
  std::vector<double> h;          ///< smoothing length, m
  std::vector<double> d0;         ///< initial diameter cbrt(V0), m
  std::vector<double> dt;         ///< stable time step estimate, s
  std::vector<PointState> state;  ///< stress and history variables
  std::vector<int> body;          ///< owning body
  std::vector<int> material;      ///< index into Model::materials
  std::vector<int> parent;        ///< element it came from, -1 if born a particle
  std::vector<Tie> tie;
  /// Identity through renumbering (particle_order.hpp): the order of birth, 0, 1, ...
  std::vector<int> id;
  std::size_t size() const { return x.size(); }
};

/// Which way a body is discretised at start.
enum class Discretisation { Fem, Sph };

struct Body {
  std::string name;
  int material = -1;
  Discretisation discretisation = Discretisation::Fem;
  bool is_projectile = false;  ///< its velocity is the one reported as "projectile velocity"
  std::size_t node_begin = 0, node_end = 0;  ///< its nodes are [node_begin, node_end)
  std::size_t elem_begin = 0, elem_end = 0;  ///< its elements are [elem_begin, elem_end)
};

/// Frictionless (or Coulomb) rigid plane: nodes stay on the side the normal points to.
struct RigidWall {
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  ///< unit, pointing into the allowed half space
  double friction = 0.0;
};

/// Energy budget by term, J. Work done by the solver's own dissipative corrections is booked
/// so that kinetic + internal + the losses stays equal to the initial energy.
struct EnergyBudget {
  double kinetic = 0;         ///< sum 1/2 m v^2 over nodes and particles
  double internal = 0;        ///< elastic + plastic work stored in live elements and particles
  double bulk_viscosity = 0;  ///< work of the bulk viscosity (included in `internal`)
  double artificial_viscosity = 0;  ///< work of the SPH artificial viscosity (in `internal`)
  double plastic_work = 0;    ///< plastic work (included in `internal`)
  double contact = 0;         ///< energy dissipated by kinematic contact, ties and walls
  double contact_through_half = 0;  ///< the same, through the last half step t^{n+1/2}
  double eroded = 0;          ///< kinetic + internal energy of deleted elements
  double conversion = 0;      ///< kinetic energy jump of element -> particle conversion
  double initial = 0;         ///< total at t = 0
  double kinetic_half = 0;    ///< kinetic energy at the last half step, after corrections
  Vec3 momentum = Vec3::Zero();  ///< linear momentum at the last half step, kg m/s
  double time = 0;            ///< the time t^n the terms above refer to, s
  /// The step index n of `time`: the budget at t^n is closed within the step from t^n (the
  /// kinetic energy needs the half step after it), so it is one behind the model's step count.
  long step = 0;
  double total() const { return kinetic + internal + contact + eroded + conversion; }
  /// |total - initial| / initial.
  double balanceError() const {
    return initial > 0 ? std::abs(total() - initial) / initial : 0.0;
  }
};

/// Kinematic contact between bodies ([contact] in a scene).
struct ContactControls {
  int passes = 3;         ///< relaxed correction passes per step, N (paper: 2-5)
  double friction = 0.0;  ///< Coulomb coefficient between bodies
  /// How far behind a face, as a fraction of its longest edge, a node may start the step and
  /// still be held by it (kept from going deeper). Deeper nodes went through the other side
  /// of a thin body, or were never outside: that face is not the one they crossed.
  double depth_tolerance = 0.2;
};

/// What happens to elements that fail or distort ([conversion] in a scene).
enum class ConversionMode { None, Erosion, Sph };
struct ConversionControls {
  ConversionMode mode = ConversionMode::None;
  double plastic_strain = 0.4;  ///< eps_p at which an element erodes or converts
  // Safety triggers, so a run never dies of a distorted element (counted apart):
  double min_volume_ratio = 0.05;  ///< V/V0 below this
  double max_volume_ratio = 20.0;  ///< V/V0 above this
  /// smallest altitude below this fraction of its first: the geometric part of the stable
  /// step has collapsed (the viscous part shrinks in any strong shock and must not trigger)
  double min_dt_ratio = 0.1;
};

/// Counts of what the conversion layer did.
struct ConversionStats {
  long eroded = 0;      ///< elements deleted (erosion mode)
  long converted = 0;   ///< elements turned into particles (sph mode)
  long by_damage = 0;   ///< of those, triggered by full damage (before eps_p reached its threshold)
  long by_safety = 0;   ///< of those, triggered by a safety criterion
  double eroded_mass = 0;  ///< kg removed by erosion
};

/// Solver controls read from the scene.
struct SolverControls {
  ContactControls contact;
  ConversionControls conversion;
  double end_time = 0;
  double courant = 0.5;          ///< fraction of the element stable step
  double bulk_linear = 0.06;     ///< linear bulk viscosity coefficient
  double bulk_quadratic = 1.5;   ///< quadratic bulk viscosity coefficient
  bool average_nodal_pressure = true;  ///< ANP on the volumetric part (anti-locking)
  /// Share of the element's own volumetric response blended into ANP, so that an element's
  /// own volume cannot collapse unresisted (0: pure ANP; 1: no averaging).
  double anp_element_fraction = 0.01;
  double dt_growth = 1.1;        ///< largest step-to-step growth of dt
  double dt_min = 1e-13;         ///< a step below this stops the run, s
};

struct Model {
  Nodes nodes;
  Elements elems;
  Particles particles;
  std::vector<Body> bodies;
  std::vector<Material> materials;
  std::vector<RigidWall> walls;
  std::vector<SymmetryPlane> symmetry;  ///< at most one per axis
  Surfaces surfaces;  ///< exterior faces of every body, for contact
  SphWorkspace sph;   ///< SPH parameters and the storage reused from step to step
  SolverControls controls;
  EnergyBudget energy;
  ConversionStats conversion;

  // Node -> element-corner lists (CSR) for the deterministic force gather and nodal averages.
  std::vector<std::size_t> node_corner_offset;  ///< size nodes+1
  std::vector<std::uint32_t> node_corners;      ///< element * 4 + corner

  // scratch arrays owned here so the step allocates nothing
  std::vector<std::array<Vec3, 4>> corner_force;  ///< per element, N
  /// Each node's V / V0 over its live elements (ANP), taken once a node in the element pass
  /// and read at every corner (not in the checkpoint: taken again before it is read).
  std::vector<double> nodal_volume_ratio;
  /// Velocities before the corrections (written by each step before it reads them: not in
  /// the checkpoint).
  std::vector<Vec3> v_node_free, v_particle_free;

  double time = 0;       ///< s
  double dt = 0;         ///< last time step, s
  long step = 0;
  std::string dt_limiter;  ///< what set the last time step
  PhaseTimes timing;       ///< wall time by phase and work done, for the figures of merit
};

}  // namespace fesph
