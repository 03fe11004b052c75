// SPDX-License-Identifier: MIT
// SPH parameters and the per-step storage of the SPH layer (neighbour lists, pair kernel
// values, per-particle tensors), kept between steps so that a step allocates nothing.
#pragma once

#include "core/common/types.hpp"
#include "core/material/material.hpp"
#include "core/sph/neighbours.hpp"

#include <cstdint>
#include <utility>
#include <vector>

namespace fesph {

struct Model;

/// SPH numerical parameters. Defaults and their reasons are in docs/sph.md.
struct SphControls {
  double kappa = 1.3;         ///< h = kappa cbrt(V) for new particles (about 74 neighbours)
  // Monaghan artificial viscosity. alpha = 1, beta = 2 (the shock-tube values) turned a third
  // of the Taylor bar's impact energy into heat and left it 8-13 % too long; 0.1 / 0.5 (the
  // IMPETUS *SPH defaults) pass it (docs/sph.md). Scenes can set them ([sph]).
  double av_alpha = 0.1;      ///< linear term
  double av_beta = 0.5;       ///< quadratic term
  bool artificial_stress = true;  ///< Monaghan 2000 tensile-instability remedy on/off
  double as_epsilon = 0.3;    ///< artificial stress factor
  double max_condition = 1e3; ///< cond(A) above this: plain (normalised) kernel gradient
  int min_neighbours = 6;     ///< fewer neighbours: plain (normalised) kernel gradient
  int as_exponent = 4;        ///< artificial stress exponent n in (W(r)/W(dp))^n
  int contact_passes = 3;     ///< Gauss-Seidel passes of the particle-particle contact
  /// Verlet skin of the neighbour list, as a fraction of h: candidates within (1 + skin/2) of
  /// the support, rebuilt when a particle has drifted by skin/2 h. Never changes a result,
  /// only the cost: 0.3 holds ~1.5x the pairs and rebuilds every ~10 steps at 500 m/s.
  double verlet_skin = 0.3;
  /// Extra factor on the particle step (the solver's Courant factor applies on top). Freshly
  /// converted particles with 6-8 neighbours carry the element's compression and oscillated
  /// (J 0.87 -> 1.57 -> 0.66) at Courant 0.5; 0.4 x 0.5 = 0.2 kept the energy budget of
  /// converting bars within 0.4 % (docs/sph.md).
  double dt_factor = 0.4;
  /// Steps between renumberings of the particles in spatial order (particle_order.hpp); 0:
  /// never. Each forces a rebuild of the neighbour lists, about one step's SPH cost.
  long order_interval = 50;
};

/// The particle quantities one step's forces were computed from. Keeping the previous step's
/// copy makes the kinematics and the energy bookkeeping centred in time, as the elements' are.
struct SphSnapshot {
  std::vector<Vec3> x, v;         ///< position x^n, velocity v^{n-1/2}
  std::vector<double> h;          ///< smoothing length
  std::vector<double> V;          ///< volume at t^n weighting the sums and forces (predicted)
  std::vector<double> volume_rate;  ///< d ln V / dt over the interval ending at t^n, 1/s
  std::vector<double> rho, c, d;  ///< density, wave speed, spacing cbrt(V)
  std::vector<Mat3> B;            ///< first-order gradient correction
  std::vector<Mat3> R;            ///< Monaghan artificial stress (stress units, Pa)
  std::vector<std::uint8_t> tensile;  ///< R != 0
  void resize(std::size_t n);
  std::size_t size() const { return x.size(); }
};

/// A mirror image of the particles across the symmetry planes (one per plane, and the
/// combinations of planes): the pairs each particle forms with the image's particles, for the
/// SPH sums and for the contact across bodies. Rebuilt at every step.
struct MirrorImage {
  Reflection map;
  NeighbourList neighbours;             ///< row i: j whose image is an SPH neighbour of i
  std::vector<Vec3> grad;               ///< grad_i W(x_i - M x_j, h_ij) per entry, 1/m^4
  std::vector<Vec3> grad_prev;          ///< the same in the last step's configuration
  NeighbourList contact;                ///< row i: j > i of another body whose image is near
};

/// Storage reused from step to step, owned by the Model; the SPH functions resize it as the particle count changes. Particles
/// are assumed to keep their index between steps (new ones appended).
struct SphWorkspace {
  SphControls controls;
  NeighbourSearch search;
  NeighbourList neighbours;
  std::vector<Vec3> pair_grad;          ///< grad_i W(x_i - x_j, h_ij) per neighbour entry, 1/m^4
  /// The last step's neighbours and pair_grad: its gradients are this step's gradients in the
  /// previous configuration (the same configuration, the same bits), looked up instead of
  /// computed again.
  NeighbourList neighbours_last;
  std::vector<Vec3> pair_grad_last;
  /// Stabilisation force of each pair (this step's and the last step's lists): the last
  /// step's value is this step's previous-configuration term, the same bits, not recomputed.
  std::vector<Vec3> pair_stab, pair_stab_last;
  /// Entry of each pair in the last step's list, or kNoLastPair. 32 bits: the pair arrays are
  /// streamed twice a step (though their bytes are not what limits it:
  /// docs/performance-history.md, nineteenth session).
  std::vector<std::uint32_t> pair_last_slot;
  static constexpr std::uint32_t kNoLastPair = static_cast<std::uint32_t>(-1);
  SphSnapshot current, previous;
  std::vector<std::uint8_t> corrected;  ///< 1: B_i = A_i^-1; 0: normalised plain gradient
  std::vector<Mat3> velocity_grad;      ///< L_i at this step's positions, 1/s
  std::vector<Mat3> velocity_grad_prev; ///< L_i at the last step's positions, 1/s
  std::vector<Mat3> stress_b;           ///< sigma_i B_i, Pa
  std::vector<double> plastic_work;     ///< per particle over the last step, J
  std::vector<double> av_work;          ///< stabilisation heat per particle, last step, J
  std::vector<double> internal_energy;  ///< m e per particle after the step, J (scratch)
  /// Each particle's flow stress factors from its last step (material.hpp): scratch, not in
  /// the checkpoint, emptied when the particles are renumbered.
  std::vector<YieldCache> yield_cache;
  std::vector<double> contact_radius;   ///< m
  std::vector<double> contact_spacing;  ///< m
  std::vector<std::pair<int, int>> contact_pairs;
  std::vector<MirrorImage> mirrors;     ///< one per mirror image of the symmetry planes
};

/// computeParticleForces (sph_forces.hpp) with explicit storage and parameters.
void computeParticleForces(Model& model, double dt_last, SphWorkspace& ws);

/// enforceParticleContact (sph_forces.hpp) with explicit storage and parameters.
void enforceParticleContact(Model& model, double dt, SphWorkspace& ws);

}  // namespace fesph
