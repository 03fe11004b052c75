// SPDX-License-Identifier: MIT
#include "core/solver/step.hpp"

#include "core/common/error.hpp"
#include "core/common/ordered_sum.hpp"
#include "core/contact/node_face_contact.hpp"
#include "core/conversion/convert.hpp"
#include "core/conversion/erosion.hpp"
#include "core/conversion/particle_face_contact.hpp"
#include "core/conversion/ties.hpp"
#include "core/fem/element_forces.hpp"
#include "core/solver/boundary.hpp"
#include "core/sph/particle_order.hpp"
#include "core/sph/sph_forces.hpp"

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>
#include <string>

namespace fesph {

namespace {

/// Loops shorter than this run on one thread: a parallel region costs microseconds, and far
/// more on a loaded machine, where every barrier waits for a core.
constexpr long kParallelMin = 2048;

struct KineticSums {
  double energy = 0;
  Vec3 momentum = Vec3::Zero();
};

KineticSums kineticSums(const Model& model) {
  // fixed-order sums: the budget has the same bits for any thread count
  const Nodes& nd = model.nodes;
  const Particles& pa = model.particles;
  auto add = [](double m, const Vec3& v, std::array<double, 4>& s) {
    s[0] += 0.5 * m * v.squaredNorm();
    s[1] += m * v.x();
    s[2] += m * v.y();
    s[3] += m * v.z();
  };
  const std::array<double, 4> n = orderedSums<4>(
      nd.size(), [&](std::size_t a, std::array<double, 4>& s) { add(nd.m[a], nd.v[a], s); });
  const std::array<double, 4> p = orderedSums<4>(
      pa.size(), [&](std::size_t i, std::array<double, 4>& s) { add(pa.m[i], pa.v[i], s); });
  return {n[0] + p[0], Vec3(n[1] + p[1], n[2] + p[2], n[3] + p[3])};
}

const char* nonFiniteQuantity(const Vec3& x, const Vec3& v, const Vec3& f) {
  return !x.allFinite() ? "position" : !v.allFinite() ? "velocity" : !f.allFinite() ? "force" : nullptr;
}

// Name the first node or particle whose state is not finite, the element it belongs to and
// the body, so that the user can find it in the last output.
[[noreturn]] void reportNonFinite(const Model& model) {
  const std::string at = " at t = " + seconds(model.time);
  const Nodes& nd = model.nodes;
  for (std::size_t a = 0; a < nd.size(); ++a) {
    const char* what = nd.m[a] > 0 ? nonFiniteQuantity(nd.x[a], nd.v[a], nd.f[a]) : nullptr;
    if (!what) continue;
    std::string elem;
    if (model.node_corner_offset.size() > a + 1 &&
        model.node_corner_offset[a] < model.node_corner_offset[a + 1])
      elem = " (element " + std::to_string(model.node_corners[model.node_corner_offset[a]] / 4) + ")";
    throw RunError(std::string("non-finite ") + what + " at node " + std::to_string(a) + elem +
                   " of body '" + model.bodies[nd.body[a]].name + "'" + at +
                   ": the solution has blown up (too large a time step, a material or contact "
                   "instability, or non-physical input)");
  }
  const Particles& pa = model.particles;
  for (std::size_t i = 0; i < pa.size(); ++i) {
    const char* what = nonFiniteQuantity(pa.x[i], pa.v[i], pa.f[i]);
    if (!what) continue;
    const std::string from =
        pa.parent[i] >= 0 ? " (from element " + std::to_string(pa.parent[i]) + ")" : "";
    throw RunError(std::string("non-finite ") + what + " at particle " + std::to_string(i) +
                   from + " of body '" + model.bodies[pa.body[i]].name + "'" + at +
                   ": the solution has blown up");
  }
  throw RunError("non-finite kinetic energy" + at + " (velocities too large to square)");
}

// "element 12" -> "element 12 of body 'plate'"; other limiters unchanged.
std::string describeLimiter(const Model& model, const std::string& limiter) {
  const auto space = limiter.find(' ');
  if (space == std::string::npos) return limiter;
  const std::string kind = limiter.substr(0, space);
  const std::size_t k = std::strtoul(limiter.c_str() + space + 1, nullptr, 10);
  int body = -1;
  if (kind == "element" && k < model.elems.size()) body = model.elems.body[k];
  if (kind == "particle" && k < model.particles.size()) body = model.particles.body[k];
  return body < 0 ? limiter : limiter + " of body '" + model.bodies[body].name + "'";
}

/// Element-steps and particle-steps of this step, for the figures of merit.
void countStepWork(Model& model) {
  const ConversionStats& cs = model.conversion;
  model.timing.element_steps +=
      static_cast<double>(model.elems.size()) - static_cast<double>(cs.eroded + cs.converted);
  model.timing.particle_steps += static_cast<double>(model.particles.size());
  ++model.timing.steps;
}

}  // namespace

double stableTimeStep(Model& model, double t_stop) {
  // min is exact in any order; the limiter is the lowest index that attains it
  const Elements& el = model.elems;
  const Particles& pa = model.particles;
  const long ne = static_cast<long>(el.size()), np = static_cast<long>(pa.size());
  double dt_elem = std::numeric_limits<double>::infinity(), dt_part = dt_elem;
#pragma omp parallel for schedule(static) reduction(min : dt_elem) if (ne > kParallelMin)
  for (long e = 0; e < ne; ++e)
    if (el.status[e] == ElemStatus::Live) dt_elem = std::min(dt_elem, el.dt[e]);
#pragma omp parallel for schedule(static) reduction(min : dt_part) if (np > kParallelMin)
  for (long i = 0; i < np; ++i) dt_part = std::min(dt_part, pa.dt[i]);
  const bool by_particle = dt_part < dt_elem;
  const double dt_min = by_particle ? dt_part : dt_elem;
  long first = by_particle ? np : ne;
#pragma omp parallel for schedule(static) reduction(min : first) if (ne + np > kParallelMin)
  for (long k = 0; k < (by_particle ? np : ne); ++k) {
    const bool hit = by_particle ? pa.dt[k] == dt_min
                                 : el.status[k] == ElemStatus::Live && el.dt[k] == dt_min;
    if (hit) first = std::min(first, k);
  }
  std::string limiter = (by_particle ? "particle " : "element ") +
                        std::to_string(first == (by_particle ? np : ne) ? 0 : first);
  double dt = model.controls.courant * dt_min;
  model.dt_limiter = limiter;
  if (model.dt > 0 && dt > model.controls.dt_growth * model.dt) {
    dt = model.controls.dt_growth * model.dt;
    model.dt_limiter = "growth cap";
  }
  if (!(dt >= model.controls.dt_min))
    throw RunError("time step " + seconds(dt) + " below its floor [simulation].dt_min = " +
                   seconds(model.controls.dt_min) + " at t = " + seconds(model.time) +
                   ", limited by " + describeLimiter(model, limiter) +
                   ": its stable step collapsed (distorted, compressed or very fast)");
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
  const Particles& pa = model.particles;
  auto add = [dt_avg](double m, const Vec3& v, const Vec3& v_free, const Vec3& f,
                      std::array<double, 1>& s) {
    const Vec3 dv = v - v_free;
    if (dv.isZero(0)) return;
    const Vec3 v_prev = v_free - (dt_avg / m) * f;
    s[0] += m * dv.dot(0.5 * (v_prev + v));
  };
  const double work_nodes =
      orderedSums<1>(nd.size(), [&](std::size_t a, std::array<double, 1>& s) {
        if (nd.m[a] > 0) add(nd.m[a], nd.v[a], model.v_node_free[a], nd.f[a], s);
      })[0];
  const double work_particles =
      orderedSums<1>(pa.size(), [&](std::size_t i, std::array<double, 1>& s) {
        add(pa.m[i], pa.v[i], model.v_particle_free[i], pa.f[i], s);
      })[0];
  return work_nodes + work_particles;
}

// A budget that no longer closes to this fraction of the initial energy means the solution
// has gone unstable: runs close theirs to 0.001-0.1 %. Found in the step it happens, not
// thousands of steps later when a time step collapses or a value overflows.
constexpr double kMaxEnergyError = 0.1;

// Name the node or particle with the largest kinetic energy: an instability grows there.
[[noreturn]] void reportEnergyRunaway(const Model& model) {
  const Nodes& nd = model.nodes;
  const Particles& pa = model.particles;
  double worst = -1;
  std::string where;
  for (std::size_t a = 0; a < nd.size(); ++a)
    if (const double k = 0.5 * nd.m[a] * nd.v[a].squaredNorm(); k > worst)
      worst = k, where = "node " + std::to_string(a) + " of body '" +
                         model.bodies[nd.body[a]].name + "' at " +
                         std::to_string(nd.v[a].norm()) + " m/s";
  for (std::size_t i = 0; i < pa.size(); ++i)
    if (const double k = 0.5 * pa.m[i] * pa.v[i].squaredNorm(); k > worst)
      worst = k, where = "particle " + std::to_string(i) + " of body '" +
                         model.bodies[pa.body[i]].name + "' at " +
                         std::to_string(pa.v[i].norm()) + " m/s";
  const EnergyBudget& en = model.energy;
  throw RunError("energy balance error " + std::to_string(100 * en.balanceError()) +
                 " % of the initial " + std::to_string(en.initial) + " J at t = " +
                 seconds(model.time) + " (more than " + std::to_string(100 * kMaxEnergyError) +
                 " %): the solution has gone unstable; the most kinetic energy is at " + where);
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
  en.step = model.step;
  if (en.balanceError() > kMaxEnergyError) reportEnergyRunaway(model);
}

void integrateVelocities(Model& model, double dt_avg) {
  Nodes& nd = model.nodes;
#pragma omp parallel for schedule(static) if (nd.size() > kParallelMin)
  for (std::size_t a = 0; a < nd.size(); ++a) {
    if (nd.m[a] > 0) nd.v[a] += (dt_avg / nd.m[a]) * nd.f[a];
  }
  Particles& pa = model.particles;
#pragma omp parallel for schedule(static) if (pa.size() > kParallelMin)
  for (std::size_t i = 0; i < pa.size(); ++i) pa.v[i] += (dt_avg / pa.m[i]) * pa.f[i];
}

void integratePositions(Model& model, double dt) {
  Nodes& nd = model.nodes;
#pragma omp parallel for schedule(static) if (nd.size() > kParallelMin)
  for (std::size_t a = 0; a < nd.size(); ++a) {
    if (nd.m[a] > 0) nd.x[a] += dt * nd.v[a];
  }
  Particles& pa = model.particles;
#pragma omp parallel for schedule(static) if (pa.size() > kParallelMin)
  for (std::size_t i = 0; i < pa.size(); ++i) pa.x[i] += dt * pa.v[i];
}

/// The velocities before the corrections, whose work correctionWork books. Copied in parallel:
/// the nodes' alone (a megabyte at 200k elements) took ~1 % of an FE-SPH step in one thread
/// while the other waited.
void keepFreeVelocities(Model& model) {
  const Nodes& nd = model.nodes;
  const Particles& pa = model.particles;
  model.v_node_free.resize(nd.size());
  model.v_particle_free.resize(pa.size());
#pragma omp parallel if (nd.size() + pa.size() > kParallelMin)
  {
#pragma omp for schedule(static) nowait
    for (std::size_t a = 0; a < nd.size(); ++a) model.v_node_free[a] = nd.v[a];
#pragma omp for schedule(static)
    for (std::size_t i = 0; i < pa.size(); ++i) model.v_particle_free[i] = pa.v[i];
  }
}

void step(Model& model, double t_stop) {
  PhaseClock clock(model.timing);
  if (orderParticlesIfDue(model)) clock.lap(Phase::Particles);  // neighbours close in memory
  const double dt_last = model.dt;
  switch (model.controls.conversion.mode) {  // on the state the last step left
    case ConversionMode::Erosion: erodeElements(model); break;
    case ConversionMode::Sph: convertElements(model, model.sph.controls.kappa); break;
    case ConversionMode::None: break;
  }
  clock.lap(Phase::Conversion);
  computeElementForces(model, dt_last);   // stress and forces at t^n (inverted: converted)
  releaseTies(model);                     // faces gone with this step's conversions
  clock.lap(Phase::Elements);
  computeParticleForces(model, dt_last);  // SPH within each body, at t^n
  clock.lap(Phase::Particles);
  const double dt = stableTimeStep(model, t_stop);
  const double dt_avg = 0.5 * (dt_last + dt);
  clock.lap(Phase::TimeStep);
  integrateVelocities(model, dt_avg);     // v^{n+1/2}, free of constraints
  applyFixedVelocities(model);
  clock.lap(Phase::Integrate);

  // Kinematic constraints: velocity corrections on v^{n+1/2}.
  keepFreeVelocities(model);
  enforceRigidWalls(model, dt);
  enforceNodeFaceContact(model, dt, model.controls.contact);  // element bodies, both ways
  clock.lap(Phase::Contact);
  enforceParticleFaceContact(model, dt, model.controls.contact.passes);
  enforceTies(model, model.controls.contact.passes);  // converted particles stay coupled
  clock.lap(Phase::Coupling);
  enforceParticleContact(model, dt);      // particles of different bodies: compression only
  enforceSymmetryPlanes(model, dt);       // particles stay on their side of a symmetry plane
  clock.lap(Phase::ParticleContact);
  const double dissipated = -correctionWork(model, dt_avg);

  recordEnergyBudget(model, dissipated);  // budget at t^n
  clock.lap(Phase::Energy);
  integratePositions(model, dt);          // x^{n+1}
  clock.lap(Phase::Integrate);
  model.time += dt;
  model.dt = dt;
  ++model.step;
  countStepWork(model);
}

}  // namespace fesph
