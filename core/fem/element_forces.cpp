// SPDX-License-Identifier: MIT
#include "core/fem/element_forces.hpp"

#include "core/common/error.hpp"
#include "core/common/ordered_sum.hpp"
#include "core/conversion/convert.hpp"
#include "core/conversion/triggers.hpp"
#include "core/fem/tet4.hpp"
#include "core/mesh/mesh.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace fesph {

namespace {

/// The four nodes of an element, by reference: copying them (24-byte vectors) onto the stack
/// cost more than the arithmetic on them (store-forwarding stalls on the reloads).
struct Corners {
  std::array<const Vec3*, 4> p;
  Corners(const std::vector<Vec3>& field, const std::array<int, 4>& n)
      : p{&field[n[0]], &field[n[1]], &field[n[2]], &field[n[3]]} {}
  const Vec3& operator[](int k) const { return *p[k]; }
};

[[noreturn]] void invertedElement(const Model& model, std::size_t e) {
  const Body& b = model.bodies[model.elems.body[e]];
  throw RunError("element " + std::to_string(e) + " of body '" + b.name +
                 "' inverted at t = " + seconds(model.time) +
                 " (no conversion or erosion mode to catch it)");
}

/// An element's deviatoric step as the trapezoidal deviatoric work needs it once the stress
/// after the step is final: the stress before, the rate, the midpoint volume.
struct DeviatoricStep {
  std::size_t e;
  Sym s_old, D;
  double volume;  ///< at the midpoint configuration, m^3
};

/// Pass A's scratch for one block of elements: the yielding ones' steps and their returns.
struct PassAScratch {
  std::vector<DeviatoricStep> steps;
  std::vector<PendingReturn> returns;
};

// The trapezoidal deviatoric power over the interval into the element's energy, once its
// deviatoric stress is final.
void finishDeviatoricWork(Model& model, const DeviatoricStep& y, double dt) {
  Elements& el = model.elems;
  PointState& st = el.state[y.e];
  const double dev_work = 0.5 * (y.s_old + st.s).dot(y.D) * y.volume * dt;
  const double mass = model.materials[el.material[y.e]].rho0 * el.V0[y.e];
  st.e += dev_work / mass;
}

// Pass A up to the return: strain rate at the midpoint configuration of the last interval,
// deviatoric trial, new volume. An element that yields is appended to `yielding`, the rest
// is done (its plastic work is 0). Returns false when the element has inverted (its state is
// left as it was).
bool updateKinematicsAndTrial(Model& model, std::size_t e, double dt, PassAScratch& yielding) {
  Elements& el = model.elems;
  const Nodes& nd = model.nodes;
  const Material& mat = model.materials[el.material[e]];
  const auto& c = el.conn[e];
  const Corners x(nd.x, c), v(nd.v, c);

  // x^{n-1/2} = x^n - dt/2 v^{n-1/2}: the configuration at which the rate is centred.
  const double half_dt = 0.5 * dt;
  const TetGeometry gm = tetGeometry(x[0] - half_dt * v[0], x[1] - half_dt * v[1],
                                     x[2] - half_dt * v[2], x[3] - half_dt * v[3]);
  const double vol = tetVolume(x[0], x[1], x[2], x[3]);  // same bits as tetGeometry's
  if (!(vol > 0) || !(gm.volume > 0)) return false;

  Mat3 L = Mat3::Zero();  // velocityGradient (tet4.hpp) on the nodes in place
  for (int a = 0; a < 4; ++a) L.noalias() += v[a] * gm.grad[a].transpose();
  const Sym D = Sym::fromMatrix(L);
  const Mat3 W = 0.5 * (L - L.transpose());
  PointState& st = el.state[e];
  const Sym s_old = st.s;
  PendingReturn r;
  if (trialDeviatoricStress(mat, D, W, dt, el.rho[e], st, r, &el.yield_cache[e])) {
    yielding.steps.push_back({e, s_old, D, gm.volume});
    yielding.returns.push_back(r);
  } else {
    finishDeviatoricWork(model, {e, s_old, D, gm.volume}, dt);
  }

  const double mass = mat.rho0 * el.V0[e];
  el.dV[e] = vol - el.V[e];
  el.V[e] = vol;
  el.rho[e] = mass / vol;

  el.div_v[e] = D.trace();
  return true;
}

// Bulk viscosity (compression only) and the stable step l / (Q + sqrt(Q^2 + c^2)). The
// volumetric stiffness the element sees blends its nodes' average (ANP) and its own: the wave
// speed is the matching blend of the tangents at the two densities (EOS at each: avg, own).
void viscosityAndStableStep(Model& model, std::size_t e, const EosAtDensity& avg,
                            const EosAtDensity& own, double own_fraction) {
  Elements& el = model.elems;
  const SolverControls& ctl = model.controls;
  const double trD = el.div_v[e], len = el.len[e];
  const double c_wave = std::sqrt((1 - own_fraction) * avg.wave_speed_sq +
                                  own_fraction * own.wave_speed_sq);
  if (trD < 0) {
    el.q[e] = el.rho[e] * len * (ctl.bulk_quadratic * len * trD * trD -
                                 ctl.bulk_linear * c_wave * trD);
    const double Q = ctl.bulk_linear * c_wave + ctl.bulk_quadratic * len * (-trD);
    el.dt[e] = len / (Q + std::sqrt(Q * Q + c_wave * c_wave));
  } else {
    // Q = 0: len / sqrt(c^2) is len / c bit for bit (in binary floating point, rounding to
    // nearest, the root of a number's rounded square is that number), one root fewer.
    el.q[e] = 0.0;
    el.dt[e] = len / c_wave;
  }
}

// Pass C for live element e: geometry and length at x^n, volumetric deformation (own, or ANP
// blended with its own), bulk viscosity and stable step, energy and pressure, corner forces.
// Returns the internal energy (J); `q_work` receives the bulk viscosity work over the
// interval (J).
double volumetricResponseAndForces(Model& model, std::size_t e, bool anp, double& q_work) {
  Elements& el = model.elems;
  const Nodes& nd = model.nodes;
  const Material& mat = model.materials[el.material[e]];
  const auto& c = el.conn[e];
  PointState& st = el.state[e];
  const double mass = mat.rho0 * el.V0[e];

  // Volumetric deformation: the element's own, or the mean of its nodes' (ANP) blended with
  // a small share of its own. Pure ANP leaves an element's own volume unresisted: rim
  // elements of a Taylor bar were crushed to V/V0 = 0.45 and the step fell below 1 ns.
  double rho_vol = el.rho[e];
  double own = 1.0;
  if (anp) {
    double J = 0;
    for (int a = 0; a < 4; ++a) J += model.nodal_volume_ratio[c[a]];
    rho_vol = mat.rho0 / (0.25 * J);
    own = model.controls.anp_element_fraction;
  }
  // The geometry at x^n for the corner forces, and with it the element's length for its step.
  const TetGeometry g =
      tetGeometry(nd.x[c[0]], nd.x[c[1]], nd.x[c[2]], nd.x[c[3]], &el.len[e]);
  if (el.len0[e] == 0) el.len0[e] = el.len[e];
  // the EOS at both densities at once (without ANP the same density twice)
  const std::array<EosAtDensity, 2> eos = eosAtDensities(mat, rho_vol, el.rho[e]);
  const EosAtDensity& eos_avg = eos[0];
  const EosAtDensity& eos_own = eos[1];
  viscosityAndStableStep(model, e, eos_avg, eos_own, own);
  // Energy over the interval, trapezoidal in pressure: one predictor, one corrector,
  // since the Mie-Grueneisen pressure depends on the energy it updates.
  const double dV = el.dV[e];
  const double p_old = st.p, q = el.q[e];
  auto pressure = [&](double e_spec) {
    const double p_avg = eos_avg.pressure(mat, e_spec, st.damage);
    return own == 1.0 ? p_avg
                      : (1 - own) * p_avg + own * eos_own.pressure(mat, e_spec, st.damage);
  };
  double p_new = pressure(st.e - (p_old + q) * dV / mass);
  const double vol_work = -(0.5 * (p_old + p_new) + q) * dV;
  st.e += vol_work / mass;
  p_new = pressure(st.e);
  st.p = p_new;
  q_work = -q * dV;

  Mat3 sigma = st.s.matrix();
  sigma.diagonal().array() -= (st.p + q);
  for (int a = 0; a < 4; ++a) model.corner_force[e][a] = -g.volume * (sigma * g.grad[a]);
  return mass * st.e;
}

}  // namespace

void computeElementForces(Model& model, double dt_last) {
  Elements& el = model.elems;
  Nodes& nd = model.nodes;
  const std::size_t ne = el.size();
  if (el.yield_cache.size() != ne) el.yield_cache.assign(ne, YieldCache{});

  // Energy sums in a fixed order (ordered_sum.hpp): the same bits for any thread count.
  // Pass A block by block: kinematics and trial stress of every element, then the radial
  // returns of the block's yielding ones side by side (completeReturns), then their energy.
  const std::array<double, 2> a_sums = orderedBlockSums<2>(
      ne, [&](std::size_t begin, std::size_t end, std::array<double, 2>& sum) {
        thread_local PassAScratch yielding;
        yielding.steps.clear();
        yielding.returns.clear();
        for (std::size_t e = begin; e < end; ++e) {
          if (el.status[e] != ElemStatus::Live) continue;
          if (!updateKinematicsAndTrial(model, e, dt_last, yielding)) {
            el.dt[e] = -1.0;  // marks the inverted element for the serial pass below
            sum[1] += 1;
          }
        }
        completeReturns(yielding.returns.data(), yielding.returns.size());
        // The plastic work in element order (the others' is 0: adding it changes no bit).
        for (std::size_t k = 0; k < yielding.steps.size(); ++k) {
          finishDeviatoricWork(model, yielding.steps[k], dt_last);
          sum[0] += yielding.returns[k].work * yielding.steps[k].volume;
        }
      });
  const double plastic_sum = a_sums[0];
  const bool any_inverted = a_sums[1] > 0;
  // An element that inverted within one step escaped the safety triggers: in a conversion or
  // erosion run it goes the same way as a failed element (counted as safety), otherwise the
  // run stops naming it. Serial and in element order, so the result is reproducible.
  if (any_inverted) {
    for (std::size_t e = 0; e < ne; ++e) {
      if (el.status[e] != ElemStatus::Live || el.dt[e] >= 0) continue;
      if (!retireInvertedElement(model, e)) invertedElement(model, e);
    }
  }

  // Pass B: nodal volumes over live elements (average nodal pressure, Bonet & Burton 1998).
  const bool anp = model.controls.average_nodal_pressure;
  if (anp) {
    model.nodal_volume_ratio.resize(nd.size());
#pragma omp parallel for schedule(static)
    for (std::size_t a = 0; a < nd.size(); ++a) {
      double vol = 0, vol0 = 0;
      for (std::size_t k = model.node_corner_offset[a]; k < model.node_corner_offset[a + 1]; ++k) {
        const std::size_t e = model.node_corners[k] / 4;
        if (el.status[e] != ElemStatus::Live) continue;
        vol += el.V[e];
        vol0 += el.V0[e];
      }
      model.nodal_volume_ratio[a] = vol0 > 0 ? vol / vol0 : 0.0;  // 0: no live element
    }
  }

  // Pass C: volumetric response, energy, corner forces; and the conversion triggers, whose
  // inputs are final now and in cache (read at the next step's start: triggers.hpp).
  const bool triggers = model.controls.conversion.mode != ConversionMode::None;
  if (triggers) el.trigger.resize(ne, Trigger::None);
  const std::array<double, 2> c_sums =
      orderedSums<2>(ne, [&](std::size_t e, std::array<double, 2>& sum) {
        if (el.status[e] != ElemStatus::Live) return;
        double q_work = 0;
        sum[0] += volumetricResponseAndForces(model, e, anp, q_work);
        sum[1] += q_work;
        if (triggers) el.trigger[e] = elementTrigger(model, e);
      });
  if (triggers) el.trigger_step = model.step;
  // Gather the corner forces per node in a fixed order: no atomics, same result for any
  // thread count (LULESH's scheme).
#pragma omp parallel for schedule(static)
  for (std::size_t a = 0; a < nd.size(); ++a) {
    Vec3 f = Vec3::Zero();
    for (std::size_t k = model.node_corner_offset[a]; k < model.node_corner_offset[a + 1]; ++k) {
      const std::uint32_t ec = model.node_corners[k];
      if (el.status[ec / 4] != ElemStatus::Live) continue;
      f += model.corner_force[ec / 4][ec % 4];
    }
    nd.f[a] = f;
  }

  model.energy.plastic_work += plastic_sum;
  model.energy.bulk_viscosity += c_sums[1];
  model.energy.internal = c_sums[0];
}

}  // namespace fesph
