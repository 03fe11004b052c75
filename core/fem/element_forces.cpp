// SPDX-License-Identifier: MIT
#include "core/fem/element_forces.hpp"

#include "core/common/error.hpp"
#include "core/common/ordered_sum.hpp"
#include "core/conversion/convert.hpp"
#include "core/conversion/triggers.hpp"
#include "core/fem/tet4.hpp"
#include "core/material/eos_lanes.hpp"
#include "core/mesh/mesh.hpp"

#include <cmath>
#include <string>
#include <vector>

namespace fesph {

namespace {

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

// Pass A takes four elements at a time through its arithmetic (kinematics and trial stress):
// each lane of a Lanes4 is one element and takes the operations of the scalar functions it
// stands for (tetGeometry, tetVolume, the velocity gradient, Sym::fromMatrix, jaumannRate,
// the trial in trialDeviatoricStress, vonMises) in their order and without FMA, so each lane
// has their bits (tests/unit/test_fem.cpp, "pass A four elements at a time"). The lanes'
// helpers are always inlined: their vectors cross no call (CMakeLists.txt, -Wno-psabi).
using Lanes4 = double __attribute__((vector_size(32)));
// the lanes' passes cloned for AVX and the baseline, chosen at load time (x86-64 only: elsewhere
// the compiler splits the vectors to the machine's)
#if defined(__x86_64__)
#define FESPH_AVX_CLONES [[gnu::target_clones("avx", "default")]]
#else
#define FESPH_AVX_CLONES
#endif
struct Vec3L {
  Lanes4 x, y, z;
};

[[gnu::always_inline]] inline Vec3L operator-(const Vec3L& a, const Vec3L& b) {
  return {a.x - b.x, a.y - b.y, a.z - b.z};
}
[[gnu::always_inline]] inline Vec3L operator*(const Vec3L& a, Lanes4 c) {
  return {a.x * c, a.y * c, a.z * c};
}
// Eigen's cross and dot of 3-vectors, term for term (dot: t0 + (t1 + t2), its unrolled sum)
[[gnu::always_inline]] inline Vec3L cross(const Vec3L& a, const Vec3L& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
[[gnu::always_inline]] inline Lanes4 dot(const Vec3L& a, const Vec3L& b) {
  return a.x * b.x + (a.y * b.y + a.z * b.z);
}
[[gnu::always_inline]] inline Vec3L gather(const Vec3* const p[4]) {
  return {Lanes4{p[0]->x(), p[1]->x(), p[2]->x(), p[3]->x()},
          Lanes4{p[0]->y(), p[1]->y(), p[2]->y(), p[3]->y()},
          Lanes4{p[0]->z(), p[1]->z(), p[2]->z(), p[3]->z()}};
}
[[gnu::always_inline]] inline void store(double* to, Lanes4 v) {
  __builtin_memcpy(to, &v, sizeof v);
}

/// tetGeometry of four tets (corners p[0..3]): the determinant 6 V, the shape-function
/// gradients, and the cross products of the edges at corner 0 (twice the faces' areas).
struct TetLanes {
  Lanes4 det;
  Vec3L grad[4];
  Vec3L c23, c31, c12;
};
[[gnu::always_inline]] inline TetLanes tetLanes(const Vec3L p[4]) {
  const Vec3L e1 = p[1] - p[0], e2 = p[2] - p[0], e3 = p[3] - p[0];
  TetLanes t;
  t.c23 = cross(e2, e3), t.c31 = cross(e3, e1), t.c12 = cross(e1, e2);
  t.det = dot(e1, t.c23);
  const Lanes4 inv = 1.0 / t.det;
  t.grad[1] = t.c23 * inv;
  t.grad[2] = t.c31 * inv;
  t.grad[3] = t.c12 * inv;
  t.grad[0] = {-((t.grad[1].x + t.grad[2].x) + t.grad[3].x),
               -((t.grad[1].y + t.grad[2].y) + t.grad[3].y),
               -((t.grad[1].z + t.grad[2].z) + t.grad[3].z)};
  return t;
}

/// The elements e0 .. e0+3 for the lanes; a block's last group, past `end`, repeats its last
/// element in the lanes left over.
std::array<std::size_t, 4> groupOfFour(std::size_t e0, std::size_t end) {
  std::array<std::size_t, 4> group;
  for (std::size_t k = 0; k < 4; ++k) group[k] = std::min(e0 + k, end - 1);
  return group;
}

/// What pass A's arithmetic leaves for each of four elements, one row of lanes a quantity.
struct PassALanes {
  double vol_mid[4];     ///< volume at the midpoint configuration (the rate's), m^3
  double vol[4];         ///< volume at x^n, m^3
  double rho[4];         ///< density at x^n, kg/m^3
  double D[6][4];        ///< rate of deformation, 1/s (in Sym's order)
  double s_tr[6][4];     ///< trial deviatoric stress, Pa
  double sigma_eq[4];    ///< its von Mises equivalent, Pa
  double de_elastic[4];  ///< finishDeviatoricWork's energy increment if s_tr stays, J/kg
};

// Pass A's arithmetic for the four elements `group` (a group may repeat an element; a lane
// whose element is not live computes on its nodes and is ignored): the rate of deformation
// and spin at the midpoint configuration of the last interval, x^{n-1/2} = x^n - dt/2
// v^{n-1/2}, the volume and density at x^n, the deviatoric trial stress and its equivalent.
FESPH_AVX_CLONES void passALanes(const Model& model, const std::array<std::size_t, 4>& group,
                                 double dt, PassALanes& out) {
  const Elements& el = model.elems;
  const Nodes& nd = model.nodes;
  // Each lane built from registers (four loads, then the lanes joined): written lane by lane
  // in memory, a vector is read back before its stores can forward to it.
  const Vec3 *px[4][4], *pv[4][4];  // [corner][lane]
  const Sym* ps[4];
  const Material* pm[4];
  for (int k = 0; k < 4; ++k) {
    const std::size_t e = group[k];
    for (int a = 0; a < 4; ++a) {
      px[a][k] = &nd.x[el.conn[e][a]];
      pv[a][k] = &nd.v[el.conn[e][a]];
    }
    ps[k] = &el.state[e].s;
    pm[k] = &model.materials[el.material[e]];
  }
  Vec3L x[4], v[4];
  for (int a = 0; a < 4; ++a) {
    x[a] = gather(px[a]);
    v[a] = gather(pv[a]);
  }
  const Lanes4 s[6] = {
      Lanes4{ps[0]->xx, ps[1]->xx, ps[2]->xx, ps[3]->xx},
      Lanes4{ps[0]->yy, ps[1]->yy, ps[2]->yy, ps[3]->yy},
      Lanes4{ps[0]->zz, ps[1]->zz, ps[2]->zz, ps[3]->zz},
      Lanes4{ps[0]->xy, ps[1]->xy, ps[2]->xy, ps[3]->xy},
      Lanes4{ps[0]->yz, ps[1]->yz, ps[2]->yz, ps[3]->yz},
      Lanes4{ps[0]->zx, ps[1]->zx, ps[2]->zx, ps[3]->zx}};
  const Lanes4 G2dt = Lanes4{pm[0]->G, pm[1]->G, pm[2]->G, pm[3]->G} * 2.0 * dt;
  const Lanes4 mass = Lanes4{pm[0]->rho0, pm[1]->rho0, pm[2]->rho0, pm[3]->rho0} *
                      Lanes4{el.V0[group[0]], el.V0[group[1]], el.V0[group[2]], el.V0[group[3]]};
  const Lanes4 half_dt = Lanes4{} + 0.5 * dt;
  Vec3L m[4];
  for (int a = 0; a < 4; ++a) m[a] = x[a] - v[a] * half_dt;
  // tetGeometry at the midpoint, tetVolume at x^n
  const TetLanes at_mid = tetLanes(m);
  const Lanes4 det = at_mid.det;
  const Vec3L* g = at_mid.grad;
  const Lanes4 vol = dot(x[1] - x[0], cross(x[2] - x[0], x[3] - x[0])) / 6.0;
  store(out.vol_mid, det / 6.0);
  store(out.vol, vol);
  store(out.rho, mass / vol);

  // L_ij = sum_a v_a,i dN_a/dx_j from zero, as Mat3's += of outer products; D and W from it
  Lanes4 L[3][3] = {};
  for (int a = 0; a < 4; ++a) {
    const Lanes4 va[3] = {v[a].x, v[a].y, v[a].z}, ga[3] = {g[a].x, g[a].y, g[a].z};
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) L[i][j] += ga[j] * va[i];
  }
  const Lanes4 D[6] = {L[0][0], L[1][1], L[2][2], 0.5 * (L[0][1] + L[1][0]),
                       0.5 * (L[1][2] + L[2][1]), 0.5 * (L[2][0] + L[0][2])};
  Lanes4 W[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) W[i][j] = 0.5 * (L[i][j] - L[j][i]);

  // the Jaumann rotation W s - s W = M + M^T with M = W s, and the elastic trial
  // s + dt (W s - s W) + 2 G dt dev(D)
  const Lanes4 S[3][3] = {{s[0], s[3], s[5]}, {s[3], s[1], s[4]}, {s[5], s[4], s[2]}};
  Lanes4 M[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      M[i][j] = W[i][0] * S[0][j] + (W[i][1] * S[1][j] + W[i][2] * S[2][j]);
  const Lanes4 rotation[6] = {2.0 * M[0][0],     2.0 * M[1][1],     2.0 * M[2][2],
                              M[0][1] + M[1][0], M[1][2] + M[2][1], M[2][0] + M[0][2]};
  const Lanes4 mean = ((D[0] + D[1]) + D[2]) / 3.0;
  const Lanes4 dev_D[6] = {D[0] - mean, D[1] - mean, D[2] - mean, D[3], D[4], D[5]};
  Lanes4 tr[6];
  for (int k = 0; k < 6; ++k) {
    tr[k] = (s[k] + rotation[k] * dt) + dev_D[k] * G2dt;
    store(out.D[k], D[k]);
    store(out.s_tr[k], tr[k]);
  }
  // Sym::dot, for vonMises and for finishDeviatoricWork
  const auto contract = [](const Lanes4* a, const Lanes4* b) {
    return ((a[0] * b[0] + a[1] * b[1]) + a[2] * b[2]) +
           2.0 * ((a[3] * b[3] + a[4] * b[4]) + a[5] * b[5]);
  };
  const Lanes4 q = 1.5 * contract(tr, tr);
  for (int k = 0; k < 4; ++k) out.sigma_eq[k] = std::sqrt(q[k]);
  Lanes4 mid[6];
  for (int k = 0; k < 6; ++k) mid[k] = s[k] + tr[k];
  store(out.de_elastic, 0.5 * contract(mid, D) * (det / 6.0) * dt / mass);
}

// Pass A for live element e once its arithmetic is done (lane k of `a`): the trial stress and
// the new volume and density; an element that yields is appended to `yielding`, the rest is
// done (its plastic work is 0). Returns false when the element has inverted (its state is
// left as it was).
bool finishKinematicsAndTrial(Model& model, std::size_t e, double dt, const PassALanes& a,
                              int k, PassAScratch& yielding) {
  Elements& el = model.elems;
  if (!(a.vol[k] > 0) || !(a.vol_mid[k] > 0)) return false;
  const Material& mat = model.materials[el.material[e]];
  const Sym D{a.D[0][k], a.D[1][k], a.D[2][k], a.D[3][k], a.D[4][k], a.D[5][k]};
  const Sym s_tr{a.s_tr[0][k], a.s_tr[1][k], a.s_tr[2][k],
                 a.s_tr[3][k], a.s_tr[4][k], a.s_tr[5][k]};
  PointState& st = el.state[e];
  const DeviatoricStep step{e, st.s, D, a.vol_mid[k]};
  PendingReturn r;
  const bool failed = st.damage >= 1.0;  // its stress goes to 0, not to s_tr
  if (yieldsAtTrial(mat, s_tr, a.sigma_eq[k], dt, el.rho[e], st, r, &el.yield_cache[e])) {
    yielding.steps.push_back(step);
    yielding.returns.push_back(r);
  } else if (failed) {
    finishDeviatoricWork(model, step, dt);
  } else {
    st.e += a.de_elastic[k];
  }
  el.dV[e] = a.vol[k] - el.V[e];
  el.V[e] = a.vol[k];
  el.rho[e] = a.rho[k];
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

// Pass C for four elements of one material (`group`, as in pass A), each lane with the
// operations of volumetricResponseAndForces (and of tetGeometry, eosAtDensities,
// EosAtDensity::pressure and viscosityAndStableStep in it) in their order: the branches
// (compressed or expanded, viscosity in compression only, a failed point's pressure cut) are
// taken in every lane and selected. Writes what that function writes for each of the first
// `count` lanes that is live; `energy` and `q_work` receive its return value and q_work.
FESPH_AVX_CLONES void passCLanes(Model& model, const std::array<std::size_t, 4>& group,
                                 int count, bool anp, double energy[4], double q_work[4]) {
  Elements& el = model.elems;
  const Nodes& nd = model.nodes;
  const SolverControls& ctl = model.controls;
  const Material& mat = model.materials[el.material[group[0]]];
  const Vec3* px[4][4];  // [corner][lane]
  const PointState* ps[4];
  for (int k = 0; k < 4; ++k) {
    for (int a = 0; a < 4; ++a) px[a][k] = &nd.x[el.conn[group[k]][a]];
    ps[k] = &el.state[group[k]];
  }
  const auto lanes = [&](auto field) {
    return Lanes4{field(group[0], 0), field(group[1], 1), field(group[2], 2), field(group[3], 3)};
  };
  const Lanes4 rho = lanes([&](std::size_t e, int) { return el.rho[e]; });
  const Lanes4 mass = mat.rho0 * lanes([&](std::size_t e, int) { return el.V0[e]; });

  // the volumetric deformation: own, or ANP's mean of the nodes blended with a share of own
  Lanes4 rho_vol = rho;
  double own = 1.0;
  if (anp) {
    Lanes4 J = {};
    for (int a = 0; a < 4; ++a)
      J += lanes([&](std::size_t e, int) { return model.nodal_volume_ratio[el.conn[e][a]]; });
    rho_vol = mat.rho0 / (0.25 * J);
    own = ctl.anp_element_fraction;
  }

  // tetGeometry at x^n with the altitude
  Vec3L x[4];
  for (int a = 0; a < 4; ++a) x[a] = gather(px[a]);
  const TetLanes tet = tetLanes(x);
  const Lanes4 volume = tet.det / 6.0;
  const Vec3L* g = tet.grad;
  const Vec3L &c23 = tet.c23, &c31 = tet.c31, &c12 = tet.c12;
  const auto max = [](Lanes4 a, Lanes4 b) { return a < b ? b : a; };  // std::max's choice
  const Vec3L c0 = cross(x[2] - x[1], x[3] - x[1]);
  const Lanes4 largest = max(max(dot(c0, c0), dot(c23, c23)), max(dot(c31, c31), dot(c12, c12)));
  Lanes4 root, abs_volume;
  for (int k = 0; k < 4; ++k) root[k] = std::sqrt(largest[k]), abs_volume[k] = std::abs(volume[k]);
  const Lanes4 len = 3.0 * abs_volume / (0.5 * root);

  // eosAtDensities at rho_vol (avg) and rho (own)
  const EosLanes<Lanes4> eos_avg = eosLanes(mat, rho_vol), eos_own = eosLanes(mat, rho);
  const Lanes4 damage = lanes([&](std::size_t, int k) { return ps[k]->damage; });
  // EosAtDensity::pressure: Gamma0 rho0 (e - e_ref) compressed, Gamma0 rho0 e expanded
  const auto pressureAt = [&](const EosLanes<Lanes4>& eos, Lanes4 e_spec) {
    Lanes4 p = eos.p_ref;
    if (mat.eos != EosModel::Linear)
      p = eos.p_ref + mat.gamma0 * mat.rho0 * (eos.compressed ? e_spec - eos.e_ref : e_spec);
    return damage >= 1.0 ? (p < 0.0 ? Lanes4{} : p) : p;
  };
  const auto pressure = [&](Lanes4 e_spec) {
    const Lanes4 p_avg = pressureAt(eos_avg, e_spec);
    return own == 1.0 ? p_avg : (1 - own) * p_avg + own * pressureAt(eos_own, e_spec);
  };

  // viscosityAndStableStep
  const Lanes4 trD = lanes([&](std::size_t e, int) { return el.div_v[e]; });
  Lanes4 c_wave;
  {
    const Lanes4 c2 = (1 - own) * eos_avg.wave_speed_sq + own * eos_own.wave_speed_sq;
    for (int k = 0; k < 4; ++k) c_wave[k] = std::sqrt(c2[k]);
  }
  const Lanes4 q_compress = rho * len * (ctl.bulk_quadratic * len * trD * trD -
                                         ctl.bulk_linear * c_wave * trD);
  const Lanes4 Q = ctl.bulk_linear * c_wave + ctl.bulk_quadratic * len * (-trD);
  Lanes4 root_q;
  {
    const Lanes4 qq = Q * Q + c_wave * c_wave;
    for (int k = 0; k < 4; ++k) root_q[k] = std::sqrt(qq[k]);
  }
  const auto compression = trD < 0;
  const Lanes4 q = compression ? q_compress : Lanes4{};
  const Lanes4 dt = compression ? len / (Q + root_q) : len / c_wave;

  // the energy, trapezoidal in pressure (predictor, corrector)
  const Lanes4 dV = lanes([&](std::size_t e, int) { return el.dV[e]; });
  const Lanes4 p_old = lanes([&](std::size_t, int k) { return ps[k]->p; });
  Lanes4 e_spec = lanes([&](std::size_t, int k) { return ps[k]->e; });
  Lanes4 p_new = pressure(e_spec - (p_old + q) * dV / mass);
  const Lanes4 vol_work = -(0.5 * (p_old + p_new) + q) * dV;
  e_spec += vol_work / mass;
  p_new = pressure(e_spec);

  // corner forces -V sigma grad N_a with sigma = s - (p + q) I; Eigen takes the scalar -V into
  // the matrix and sums each row t0 + (t1 + t2)
  const Lanes4 pq = p_new + q, minus_volume = -volume;
  const auto scaled = [&](double Sym::*c) {
    return minus_volume * lanes([&](std::size_t, int k) { return ps[k]->s.*c; });
  };
  const Lanes4 sxx = minus_volume * (lanes([&](std::size_t, int k) { return ps[k]->s.xx; }) - pq);
  const Lanes4 syy = minus_volume * (lanes([&](std::size_t, int k) { return ps[k]->s.yy; }) - pq);
  const Lanes4 szz = minus_volume * (lanes([&](std::size_t, int k) { return ps[k]->s.zz; }) - pq);
  const Lanes4 sxy = scaled(&Sym::xy), syz = scaled(&Sym::yz), szx = scaled(&Sym::zx);
  Vec3L f[4];
  for (int a = 0; a < 4; ++a) {
    f[a].x = sxx * g[a].x + (sxy * g[a].y + szx * g[a].z);
    f[a].y = sxy * g[a].x + (syy * g[a].y + syz * g[a].z);
    f[a].z = szx * g[a].x + (syz * g[a].y + szz * g[a].z);
  }
  const Lanes4 internal = mass * e_spec, work_q = -q * dV;

  for (int k = 0; k < count; ++k) {
    const std::size_t e = group[k];
    if (el.status[e] != ElemStatus::Live) continue;
    el.len[e] = len[k];
    if (el.len0[e] == 0) el.len0[e] = len[k];
    el.q[e] = q[k];
    el.dt[e] = dt[k];
    PointState& st = el.state[e];
    st.e = e_spec[k];
    st.p = p_new[k];
    for (int a = 0; a < 4; ++a) model.corner_force[e][a] = Vec3(f[a].x[k], f[a].y[k], f[a].z[k]);
    energy[k] = internal[k];
    q_work[k] = work_q[k];
  }
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
        PassALanes lanes;
        for (std::size_t e0 = begin; e0 < end; e0 += 4) {
          const std::array<std::size_t, 4> group = groupOfFour(e0, end);
          const int count = static_cast<int>(std::min<std::size_t>(4, end - e0));
          passALanes(model, group, dt_last, lanes);
          for (int k = 0; k < count; ++k) {
            const std::size_t e = e0 + k;
            if (el.status[e] != ElemStatus::Live) continue;
            if (!finishKinematicsAndTrial(model, e, dt_last, lanes, k, yielding)) {
              el.dt[e] = -1.0;  // marks the inverted element for the serial pass below
              sum[1] += 1;
            }
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
  // Groups of four elements of one material take the lanes (passCLanes), the others (where
  // bodies meet) one element at a time.
  const std::array<double, 2> c_sums = orderedBlockSums<2>(
      ne, [&](std::size_t begin, std::size_t end, std::array<double, 2>& sum) {
        for (std::size_t e0 = begin; e0 < end; e0 += 4) {
          const std::array<std::size_t, 4> group = groupOfFour(e0, end);
          const int count = static_cast<int>(std::min<std::size_t>(4, end - e0));
          double energy[4], q_work[4] = {};
          const bool one_material = el.material[group[0]] == el.material[group[1]] &&
                                    el.material[group[0]] == el.material[group[2]] &&
                                    el.material[group[0]] == el.material[group[3]];
          if (one_material) passCLanes(model, group, count, anp, energy, q_work);
          for (int k = 0; k < count; ++k) {
            const std::size_t e = e0 + k;
            if (el.status[e] != ElemStatus::Live) continue;
            if (!one_material) energy[k] = volumetricResponseAndForces(model, e, anp, q_work[k]);
            sum[0] += energy[k];
            sum[1] += q_work[k];
            if (triggers) el.trigger[e] = elementTrigger(model, e);
          }
        }
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
