// SPDX-License-Identifier: MIT
#include "core/solver/step.hpp"

#include "core/common/error.hpp"
#include "core/contact/node_face_contact.hpp"
#include "core/conversion/convert.hpp"
#include "core/conversion/erosion.hpp"
#include "core/conversion/particle_face_contact.hpp"
#include "core/conversion/ties.hpp"
#include "core/fem/element_forces.hpp"
#include "core/solver/boundary.hpp"
#include "core/sph/sph_forces.hpp"

#include <cmath>
#include <limits>
#include <string>

namespace fesph {

namespace {

struct KineticSums {
  double energy = 0;
  Vec3 momentum = Vec3::Zero();
};

KineticSums kineticSums(const Model& model) {
  const Nodes& nd = model.nodes;
  double ke = 0, px = 0, py = 0, pz = 0;
#pragma omp parallel for schedule(static) reduction(+ : ke, px, py, pz)
  for (std::size_t a = 0; a < nd.size(); ++a) {
    const double m = nd.m[a];
    ke += 0.5 * m * nd.v[a].squaredNorm();
    px += m * nd.v[a].x();
    py += m * nd.v[a].y();
    pz += m * nd.v[a].z();
  }
  const Particles& pa = model.particles;
#pragma omp parallel for schedule(static) reduction(+ : ke, px, py, pz)
  for (std::size_t i = 0; i < pa.size(); ++i) {
    const double m = pa.m[i];
    ke += 0.5 * m * pa.v[i].squaredNorm();
    px += m * pa.v[i].x();
    py += m * pa.v[i].y();
    pz += m * pa.v[i].z();
  }
  return {ke, Vec3(px, py, pz)};
}

[[noreturn]] void reportNonFinite(const Model& model) {
  const Nodes& nd = model.nodes;
  for (std::size_t a = 0; a < nd.size(); ++a) {
    if (nd.m[a] > 0 && !(nd.v[a].allFinite() && nd.x[a].allFinite() && nd.f[a].allFinite()))
      throw RunError("non-finite velocity or force at node " + std::to_string(a) + " of body '" +
                     model.bodies[nd.body[a]].name + "' at t = " + std::to_string(model.time) +
                     " s");
  }
  const Particles& pa = model.particles;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    if (!(pa.v[i].allFinite() && pa.x[i].allFinite() && pa.f[i].allFinite()))
      throw RunError("non-finite velocity or force at particle " + std::to_string(i) +
                     " of body '" + model.bodies[pa.body[i]].name + "' at t = " +
                     std::to_string(model.time) + " s");
  }
  throw RunError("non-finite kinetic energy at t = " + std::to_string(model.time) + " s");
}

}  // namespace

double stableTimeStep(Model& model, double t_stop) {
  const Elements& el = model.elems;
  double dt_min = std::numeric_limits<double>::infinity();
  std::size_t e_min = 0;
  for (std::size_t e = 0; e < el.size(); ++e) {
    if (el.status[e] == ElemStatus::Live && el.dt[e] < dt_min) dt_min = el.dt[e], e_min = e;
  }
  std::string limiter = "element " + std::to_string(e_min);
  const Particles& pa = model.particles;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    if (pa.dt[i] < dt_min) dt_min = pa.dt[i], limiter = "particle " + std::to_string(i);
  }
  double dt = model.controls.courant * dt_min;
  model.dt_limiter = limiter;
  if (model.dt > 0 && dt > model.controls.dt_growth * model.dt) {
    dt = model.controls.dt_growth * model.dt;
    model.dt_limiter = "growth cap";
  }
  if (!(dt >= model.controls.dt_min))
    throw RunError("time step " + std::to_string(dt) + " s below its floor " +
                   std::to_string(model.controls.dt_min) + " s at t = " +
                   std::to_string(model.time) + " s (limited by " + model.dt_limiter + ")");
  // Land exactly on t_stop without leaving a sliver of a step before it.
  const double remaining = t_stop - model.time;
  if (remaining <= dt) {
    dt = remaining;
    model.dt_limiter = "output/end time";
  } else if (remaining < 2 * dt) {
    dt = 0.5 * remaining;
    model.dt_limiter = "output/end time";
  }
  return dt;
}

double correctionWork(const Model& model, double dt_avg) {
  // A correction dv at t^{n+1/2} acts like a force m dv / dt_avg at t^n; in central
  // differences a force at t^n does the work F . (v^{n-1/2} + v^{n+1/2}) dt_avg / 2.
  // (The kinetic energy "removed" from the unconstrained v^{n+1/2} is not a loss: a node
  // held on a wall would count its whole free acceleration every step.)
  const Nodes& nd = model.nodes;
  double work = 0;
#pragma omp parallel for schedule(static) reduction(+ : work)
  for (std::size_t a = 0; a < nd.size(); ++a) {
    const Vec3 dv = nd.v[a] - model.v_node_free[a];
    if (nd.m[a] <= 0 || dv.isZero(0)) continue;
    const Vec3 v_prev = model.v_node_free[a] - (dt_avg / nd.m[a]) * nd.f[a];
    work += nd.m[a] * dv.dot(0.5 * (v_prev + nd.v[a]));
  }
  const Particles& pa = model.particles;
#pragma omp parallel for schedule(static) reduction(+ : work)
  for (std::size_t i = 0; i < pa.size(); ++i) {
    const Vec3 dv = pa.v[i] - model.v_particle_free[i];
    if (dv.isZero(0)) continue;
    const Vec3 v_prev = model.v_particle_free[i] - (dt_avg / pa.m[i]) * pa.f[i];
    work += pa.m[i] * dv.dot(0.5 * (v_prev + pa.v[i]));
  }
  return work;
}

void recordEnergyBudget(Model& model, double dissipated) {
  // Kinetic energy at t^n: the mean of the half steps around it (both after corrections).
  // A correction acts as a force at t^n over [t^{n-1/2}, t^{n+1/2}]: half of its work falls
  // before t^n (none at the first step, whose interval starts at t^0).
  const KineticSums half = kineticSums(model);
  if (!std::isfinite(half.energy)) reportNonFinite(model);
  EnergyBudget& en = model.energy;
  en.kinetic = model.step == 0 ? en.kinetic_half : 0.5 * (en.kinetic_half + half.energy);
  en.kinetic_half = half.energy;
  en.momentum = half.momentum;
  en.contact = en.contact_through_half + (model.step == 0 ? 0.0 : 0.5 * dissipated);
  en.contact_through_half += dissipated;
  en.time = model.time;
}

void integrateVelocities(Model& model, double dt_avg) {
  Nodes& nd = model.nodes;
#pragma omp parallel for schedule(static)
  for (std::size_t a = 0; a < nd.size(); ++a) {
    if (nd.m[a] > 0) nd.v[a] += (dt_avg / nd.m[a]) * nd.f[a];
  }
  Particles& pa = model.particles;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < pa.size(); ++i) pa.v[i] += (dt_avg / pa.m[i]) * pa.f[i];
}

void integratePositions(Model& model, double dt) {
  Nodes& nd = model.nodes;
#pragma omp parallel for schedule(static)
  for (std::size_t a = 0; a < nd.size(); ++a) {
    if (nd.m[a] > 0) nd.x[a] += dt * nd.v[a];
  }
  Particles& pa = model.particles;
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < pa.size(); ++i) pa.x[i] += dt * pa.v[i];
}

void step(Model& model, double t_stop) {
  const double dt_last = model.dt;
  switch (model.controls.conversion.mode) {  // on the state the last step left
    case ConversionMode::Erosion: erodeElements(model); break;
    case ConversionMode::Sph: convertElements(model, model.sph.controls.kappa); break;
    case ConversionMode::None: break;
  }
  computeElementForces(model, dt_last);   // stress and forces at t^n (inverted: converted)
  releaseTies(model);                     // faces gone with this step's conversions
  computeParticleForces(model, dt_last);  // SPH within each body, at t^n
  const double dt = stableTimeStep(model, t_stop);
  const double dt_avg = 0.5 * (dt_last + dt);
  integrateVelocities(model, dt_avg);     // v^{n+1/2}, free of constraints
  applyFixedVelocities(model);

  // Kinematic constraints: velocity corrections on v^{n+1/2}.
  model.v_node_free = model.nodes.v;
  model.v_particle_free = model.particles.v;
  enforceRigidWalls(model, dt);
  enforceNodeFaceContact(model, dt, model.controls.contact);  // element bodies, both ways
  enforceParticleFaceContact(model, dt, model.controls.contact.passes);
  enforceTies(model, model.controls.contact.passes);  // converted particles stay coupled
  enforceParticleContact(model, dt);      // particles of different bodies: compression only
  const double dissipated = -correctionWork(model, dt_avg);

  recordEnergyBudget(model, dissipated);  // budget at t^n
  integratePositions(model, dt);          // x^{n+1}
  model.time += dt;
  model.dt = dt;
  ++model.step;
}

}  // namespace fesph
