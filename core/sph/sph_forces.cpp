// SPDX-License-Identifier: MIT
// Updated-Lagrangian SPH for solids: corrected velocity gradient, material update shared with
// the elements, anti-symmetric corrected forces, artificial viscosity and artificial stress,
// stable step estimates; and the compression-only contact between particles of different
// bodies. Formulation and choices: docs/sph.md.
#include "core/sph/sph_forces.hpp"

#include "core/common/error.hpp"
#include "core/common/heap_bytes.hpp"
#include "core/common/lanes.hpp"
#include "core/sph/kernel.hpp"
#include "core/sph/sph_workspace.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <string>

namespace fesph {

namespace {

/// B_i from A_i = sum_j V_j (x_j - x_i) (x) grad W_ij (symmetric, positive semi-definite since
/// grad W_ij is parallel to x_i - x_j): A^-1 reproduces any linear field exactly. Where A is
/// ill-conditioned (too few neighbours, or a line or a sheet of them: debris) the inverse
/// amplifies noise, so the plain gradient is used, normalised by the largest eigenvalue of A
/// so that it is exact along the best-sampled direction (B = I for a full neighbourhood).
Mat3 gradientCorrection(const Mat3& A_raw, std::size_t neighbours, const SphControls& ctl,
                        bool& corrected) {
  const Mat3 A = 0.5 * (A_raw + A_raw.transpose());
  const bool enough = neighbours >= static_cast<std::size_t>(ctl.min_neighbours);
  // The cofactor inverse: exact to round-off, where rebuilding it from the closed-form
  // eigenvectors loses digits (1e-9 of a linear field's gradient).
  const Mat3 B = enough ? Mat3(A.inverse()) : Mat3::Identity();
  // cond(A) <= |A|_F |A^-1|_F. Where that bound is under half the limit, the eigenvalue test
  // below passes with room to spare (A is a sum of positive semi-definite terms, so a matrix
  // this well conditioned has only positive eigenvalues, and their rounding is ~1e-16 cond):
  // the closed-form eigensolve, trigonometry included, is skipped (every particle of a full
  // neighbourhood, two thirds late in the quick four-plate run).
  if (enough && 2.0 * A.norm() * B.norm() < ctl.max_condition) {
    corrected = true;
    return 0.5 * (B + B.transpose());
  }
  Eigen::SelfAdjointEigenSolver<Mat3> es;
  es.computeDirect(A, Eigen::EigenvaluesOnly);
  const Vec3 lam = es.eigenvalues();  // ascending
  corrected = enough && lam(2) > 0 && lam(0) * ctl.max_condition > lam(2);
  if (corrected) return 0.5 * (B + B.transpose());
  return lam(2) > 0 ? Mat3(Mat3::Identity() / lam(2)) : Mat3(Mat3::Identity());
}

/// Monaghan (2000) artificial stress of a Cauchy stress: -epsilon times its tensile principal
/// stresses, in the principal frame (Gray, Monaghan & Swift 2001, eq. 4.7, in stress units).
Mat3 artificialStress(const Mat3& sigma, double epsilon) {
  Eigen::SelfAdjointEigenSolver<Mat3> es;
  es.computeDirect(sigma);
  const Vec3 r = -epsilon * es.eigenvalues().cwiseMax(0.0);
  if (r.isZero()) return Mat3::Zero();
  const Mat3& Q = es.eigenvectors();
  return Q * r.asDiagonal() * Q.transpose();
}

/// grad_i W_ij in the last step's configuration, for a pair the last step's list lacks.
/// Inlined by force: called (rarely) in the kinematics' walk over the last configuration, it
/// made GCC keep that walk's sums in memory (across a call every SSE register is clobbered).
[[gnu::always_inline]] inline Vec3 previousGradient(const SphSnapshot& prev, std::size_t i,
                                                     std::size_t j) {
  return kernelGradient(prev.x[i] - prev.x[j], 0.5 * (prev.h[i] + prev.h[j]));
}

/// x^n (n >= 0) as n - 1 products in a row, x x ... x: the chain 1 x x ... x without its exact
/// first product. T is double or Lanes2 (lane by lane the same bits).
template <class T>
T powInt(T x, int n) {
  if (n <= 0) return T{} + 1.0;
  T y = x;
  for (int k = 1; k < n; ++k) y *= x;
  return y;
}

/// Monaghan's factor f^n = (W(r) / W(dp))^n of the artificial stress for a pair at distance r,
/// mean spacing dp and mean smoothing length h. T is double or Lanes2 (two pairs, the bits of
/// one by one).
template <class T>
T stressRatio(T r, T dp, T h, int n) {
  return powInt(kernelShape(r / h) / kernelShape(dp / h), n);
}

/// One MirrorImage per reflection of the model's symmetry planes (none without planes).
void prepareMirrors(const Model& model, SphWorkspace& ws) {
  const std::vector<Reflection> images = mirrorImages(model.symmetry);
  ws.mirrors.resize(images.size());
  for (std::size_t m = 0; m < images.size(); ++m) ws.mirrors[m].map = images[m];
}

void resizeWorkspace(SphWorkspace& ws, std::size_t n) {
  ws.current.resize(n);
  resizeSnug(ws.corrected, n);
  resizeSnug(ws.velocity_grad, n);
  resizeSnug(ws.velocity_grad_prev, n);
  resizeSnug(ws.stress_b, n);
  resizeSnug(ws.plastic_work, n);
  resizeSnug(ws.av_work, n);
  resizeSnug(ws.internal_energy, n);
  resizeSnug(ws.yield_cache, n);  // new particles' entries empty (keyed: see YieldCache)
}

/// Neighbours of particle i in this step's lists: its own body's and the mirror images'.
std::size_t neighbourCount(const SphWorkspace& ws, std::size_t i) {
  std::size_t count = ws.neighbours.offset[i + 1] - ws.neighbours.offset[i];
  for (const MirrorImage& mi : ws.mirrors)
    count += mi.neighbours.offset[i + 1] - mi.neighbours.offset[i];
  return count;
}

/// grad_i W_ij of row i's pairs into `grad`, two pairs at a time: kernelGradient's arithmetic
/// lane by lane, so the same bits, with one instruction for two pairs' square roots and
/// divisions. Computed apart from the sums over them, which then run without those long
/// chains in between: 5-10 % off the SPH step (docs/performance-history.md, twentieth session).
void pairGradients(const Particles& pa, std::size_t i, const NeighbourList& nb,
                   std::vector<Vec3>& grad) {
  const std::size_t end = nb.offset[i + 1];
  for (std::size_t k = nb.offset[i]; k < end; k += 2) {
    const std::size_t k1 = std::min(k + 1, end - 1);  // an odd row's last pair fills both lanes
    const int j0 = nb.index[k], j1 = nb.index[k1];
    const Vec3 r0 = pa.x[i] - pa.x[j0], r1 = pa.x[i] - pa.x[j1];
    const Lanes2 r = norms(r0, r1);
    const Lanes2 h = {0.5 * (pa.h[i] + pa.h[j0]), 0.5 * (pa.h[i] + pa.h[j1])};
    const Lanes2 f = kernelDWdrOverR(r, h);
    grad[k] = f[0] * r0;
    grad[k1] = f[1] * r1;
  }
}

/// The entry in the last step's list of each pair of row i in this step's (`slot`), or
/// kNoLastPair for a pair new to the list (read only for pairs of particles both in the last
/// step: j < np). Most rows are the last step's unchanged (a pair crosses the support now and
/// then): their entries follow one to one; the others take one merge walk (rows ascending).
void lastSlots(const NeighbourList& last, const NeighbourList& nb, std::size_t i, std::size_t np,
               std::vector<std::uint32_t>& slot) {
  const std::size_t k0 = nb.offset[i], k1 = nb.offset[i + 1];
  std::size_t kl = 0, kl_end = 0;
  if (i + 1 < last.offset.size()) kl = last.offset[i], kl_end = last.offset[i + 1];
  const auto row = nb.index.begin() + static_cast<std::ptrdiff_t>(k0);
  if (kl_end - kl == k1 - k0 && std::equal(row, row + static_cast<std::ptrdiff_t>(k1 - k0),
                                           last.index.begin() + static_cast<std::ptrdiff_t>(kl))) {
    for (std::size_t k = k0; k < k1; ++k) slot[k] = static_cast<std::uint32_t>(kl + (k - k0));
    return;
  }
  for (std::size_t k = k0; k < k1; ++k) {
    const std::size_t j = static_cast<std::size_t>(nb.index[k]);
    slot[k] = SphWorkspace::kNoLastPair;
    if (j >= np) continue;
    while (kl < kl_end && static_cast<std::size_t>(last.index[kl]) < j) ++kl;
    if (kl < kl_end && static_cast<std::size_t>(last.index[kl]) == j)
      slot[k] = static_cast<std::uint32_t>(kl);
  }
}

/// Pass 1 for particle i: kernel gradients of its pairs, correction B_i and velocity gradient
/// L_i = sum_j V_j (v_j - v_i) (x) (B_i grad W_ij) (V_j from pass 0), exact for linear
/// velocity fields; and the same gradient of v^{n-1/2} over the last step's configuration (the
/// exact dual of the last step's forces), whose mean with L_i centres the rate in the
/// interval, as the elements' midpoint configuration does.
void kinematics(const Particles& pa, std::size_t i, SphWorkspace& ws) {
  const NeighbourList& nb = ws.neighbours;
  SphSnapshot& cur = ws.current;
  cur.x[i] = pa.x[i];
  cur.v[i] = pa.v[i];
  cur.h[i] = pa.h[i];
  pairGradients(pa, i, nb, ws.pair_grad);
  // Two walks over the row (in L1 by now): one sum each keeps its accumulators in registers,
  // where the two sums together spilled two of them to the stack at every pair.
  OuterSum A_sum, G_sum;
  for (std::size_t k = nb.offset[i]; k < nb.offset[i + 1]; ++k) {
    const int j = nb.index[k];
    A_sum.subtract(cur.V[j] * (pa.x[i] - pa.x[j]), ws.pair_grad[k]);
  }
  for (std::size_t k = nb.offset[i]; k < nb.offset[i + 1]; ++k) {
    const int j = nb.index[k];
    G_sum.add(cur.V[j] * (pa.v[j] - pa.v[i]), ws.pair_grad[k]);
  }
  Mat3 A = A_sum.matrix(), G = G_sum.matrix();
  // The mirror images of the particles near a symmetry plane are neighbours as the other
  // half's particles are in the full model: the same sums with x_j, v_j reflected.
  for (MirrorImage& mi : ws.mirrors) {
    const NeighbourList& ml = mi.neighbours;
    for (std::size_t k = ml.offset[i]; k < ml.offset[i + 1]; ++k) {
      const int j = ml.index[k];
      const Vec3 r_ij = pa.x[i] - mi.map.point(pa.x[j]);
      const Vec3 g = kernelGradient(r_ij, 0.5 * (pa.h[i] + pa.h[j]));
      mi.grad[k] = g;
      A.noalias() -= (cur.V[j] * r_ij) * g.transpose();
      G.noalias() += (cur.V[j] * (mi.map.vector(pa.v[j]) - pa.v[i])) * g.transpose();
    }
  }
  bool corrected = false;
  const Mat3 B = gradientCorrection(A, neighbourCount(ws, i), ws.controls, corrected);
  cur.B[i] = B;
  ws.corrected[i] = corrected ? 1 : 0;
  ws.velocity_grad[i] = G * B;

  // Pairs of the last step are taken from this step's list: a pair that has just left the
  // support had a vanishing kernel gradient there (W' is continuous and zero at q = 2).
  const SphSnapshot& prev = ws.previous;
  const std::size_t np = prev.size();
  if (i >= np) {  // born this step: no previous configuration
    ws.velocity_grad_prev[i] = ws.velocity_grad[i];
    for (std::size_t k = nb.offset[i]; k < nb.offset[i + 1]; ++k)
      ws.pair_last_slot[k] = SphWorkspace::kNoLastPair;
    return;
  }
  // The last step computed the gradients of its own pairs in this very configuration: a pair
  // in both lists (found by lastSlots) takes that value, bit for bit the one computed here
  // otherwise (a pair new to the list, or the first step after a restart).
  lastSlots(ws.neighbours_last, nb, i, np, ws.pair_last_slot);
  OuterSum Gp_sum;
  for (std::size_t k = nb.offset[i]; k < nb.offset[i + 1]; ++k) {
    const std::size_t j = static_cast<std::size_t>(nb.index[k]);
    if (j >= np) continue;
    const std::uint32_t kl = ws.pair_last_slot[k];
    const Vec3 g =
        kl != SphWorkspace::kNoLastPair ? ws.pair_grad_last[kl] : previousGradient(prev, i, j);
    Gp_sum.add(prev.V[j] * (pa.v[j] - pa.v[i]), g);
  }
  Mat3 Gp = Gp_sum.matrix();
  for (MirrorImage& mi : ws.mirrors) {  // few pairs: computed again, not looked up
    const NeighbourList& ml = mi.neighbours;
    for (std::size_t k = ml.offset[i]; k < ml.offset[i + 1]; ++k) {
      const std::size_t j = static_cast<std::size_t>(ml.index[k]);
      if (j >= np) continue;
      const Vec3 g = kernelGradient(prev.x[i] - mi.map.point(prev.x[j]),
                                    0.5 * (prev.h[i] + prev.h[j]));
      mi.grad_prev[k] = g;
      Gp.noalias() += (prev.V[j] * (mi.map.vector(pa.v[j]) - pa.v[i])) * g.transpose();
    }
  }
  ws.velocity_grad_prev[i] = Gp * prev.B[i];
}

/// A fully damaged particle takes no tension (eosPressure), so its neighbours moving apart open
/// a crack rather than stretch the metal. Continuity alone would let its volume grow without
/// bound as the fragments separate (densities of 1 kg/m^3 and 5 mm smoothing lengths were seen
/// behind a plate), and with it the smoothing length, the contact radius and the wave speed
/// sqrt(K / rho) that sets the time step. The volume of a failed particle therefore stops
/// growing at rho = 0.9 rho0: room for the ~2 % thermal expansion of steel heated by some
/// hundred kelvin, and far enough from rho0 that the pressure there is 0 (rho0 c0^2 eta =
/// -0.1 rho0 c0^2 outweighs Gamma0 rho0 e), so the cap does no work.
constexpr double kFailedMinDensityRatio = 0.9;

/// The volume V a failed particle of volume V_old may reach: no growth past the cap, and none
/// at all for one already past it (it may still shrink).
double failedVolume(double V, double V_old, const Material& mat, double mass) {
  return std::min(V, std::max(V_old, mass / (kFailedMinDensityRatio * mat.rho0)));
}

/// Pass 0 for particle i: its volume at t^n, which weights this step's sums and forces. The
/// continuity update gives V^n only after the velocity gradient, whose sums need every
/// neighbour's volume first. V^{n-1} there, one step behind x^n and sigma^n, left the energy
/// update first order in the step (10 % compression: 1 % off in 10 steps). V^{n-1} carried on
/// at its last interval's rate is V^n to O(dt^2); the forces and the booked work take the
/// same volumes, so the work booked stays exactly the forces' work (docs/sph.md, item 0).
void predictVolume(const Model& model, std::size_t i, double dt, SphWorkspace& ws) {
  const Particles& pa = model.particles;
  const SphSnapshot& prev = ws.previous;
  double V = pa.V[i];
  if (i < prev.size()) V *= std::exp(prev.volume_rate[i] * dt);  // born this step: no rate
  if (V > pa.V[i] && pa.state[i].damage >= 1.0)  // only growth reads the state's cache line
    V = failedVolume(V, pa.V[i], model.materials[pa.material[i]], pa.m[i]);
  ws.current.V[i] = V;
}

/// Pass 2 for particle i over the last interval dt, as the elements do it: Jaumann /
/// Johnson-Cook / damage update with the centred rate, volume from the continuity equation,
/// trapezoidal stress work and one predictor-corrector on the EOS pressure with energy. The
/// work is the stress power of the forces at both ends of the interval (V_i sigma_i : L_i),
/// so that the energy booked is the work the forces do on the velocities.
void updateMaterial(Model& model, std::size_t i, double dt, SphWorkspace& ws) {
  Particles& pa = model.particles;
  const Material& mat = model.materials[pa.material[i]];
  PointState& st = pa.state[i];
  SphSnapshot& cur = ws.current;
  const double mass = pa.m[i];
  const Mat3& Lc = ws.velocity_grad[i];
  const Mat3& Lp = ws.velocity_grad_prev[i];
  const Mat3 L = 0.5 * (Lp + Lc);
  const Sym D = Sym::fromMatrix(L), Dc = Sym::fromMatrix(Lc), Dp = Sym::fromMatrix(Lp);
  const Mat3 W = 0.5 * (L - L.transpose());
  // The work terms take the volumes the forces at both ends of the interval take (pass 0's
  // prediction), the continuity update the particle's own.
  const double Vc = cur.V[i];
  const double Vp = i < ws.previous.size() ? ws.previous.V[i] : Vc;
  const double V_old = pa.V[i];

  const Sym s_old = st.s;
  const double wp = updateDeviatoricStress(mat, D, W, dt, pa.rho[i], st, &ws.yield_cache[i]);
  // dV/dt = V tr(D), integrated exactly for a constant rate: V stays positive
  const double rate = D.trace();
  const double V_free = V_old * std::exp(rate * dt);
  const double V_new = st.damage >= 1.0 ? failedVolume(V_free, V_old, mat, mass) : V_free;
  pa.V[i] = V_new;
  pa.rho[i] = mass / V_new;
  pa.h[i] *= std::cbrt(V_new / V_old);  // h follows density: h = h0 (rho0 / rho)^(1/3)
  ws.plastic_work[i] = wp * 0.5 * (V_old + V_new);
  // the rate the volume followed, for the next step's pass 0 (the cap's, where it held: dt > 0)
  cur.volume_rate[i] = V_new == V_free ? rate : std::log(V_new / V_old) / dt;

  st.e += 0.5 * (Vp * s_old.dot(Dp) + Vc * st.s.dot(Dc)) * dt / mass;
  const double dv_old = Vp * Dp.trace() * dt, dv_new = Vc * Dc.trace() * dt;  // m^3
  const double p_old = st.p;
  const EosAtDensity eos = eosAtDensity(mat, pa.rho[i]);
  double p_new = eos.pressure(mat, st.e - 0.5 * p_old * (dv_old + dv_new) / mass, st.damage);
  st.e -= 0.5 * (p_old * dv_old + p_new * dv_new) / mass;
  p_new = eos.pressure(mat, st.e, st.damage);
  st.p = p_new;

  cur.rho[i] = pa.rho[i];
  cur.c[i] = std::sqrt(eos.wave_speed_sq);  // waveSpeed
  cur.d[i] = std::cbrt(Vc);
  Mat3 sigma = st.s.matrix();
  sigma.diagonal().array() -= st.p;
  ws.stress_b[i] = sigma * cur.B[i];
  // The remedy acts on real tension only (hydrostatic tension, p < 0), where the tensile
  // instability grows. In compression the tensile principal stresses are the deviator's small
  // excursions, and acting on them damped a compressive wave crossing a converted segment by
  // 19 % (to 7 % with this limit; tests/verification/test_conversion.cpp).
  cur.R[i] = ws.controls.artificial_stress && st.p < 0
                 ? artificialStress(sigma, ws.controls.as_epsilon)
                 : Mat3::Zero();
  cur.tensile[i] = cur.R[i].isZero(0.0) ? 0 : 1;
}

/// Stabilisation force on i from j in the configuration `s`, with g = grad W_ij there:
/// Monaghan's artificial stress V_i V_j f^n (R_i + R_j) g, f = W(r)/W(d_ij) (Gray, Monaghan &
/// Swift 2001), and the Monaghan & Gingold (1983) viscosity -m_i m_j Pi_ij g for approaching
/// pairs. Anti-symmetric bit for bit. `mu` receives -mu_ij (>= 0) for the time step.
/// x_j, v_j, R_j: j's own (s.x[j] ...) or its mirror image's. `ratio`: the pair's f^n from
/// pairStressRatios, or null to compute it here. Inlined by force: GCC kept it a call from the
/// pair loop, whose ten arguments cost 18 % of the force pass's instructions.
[[gnu::always_inline]] inline Vec3
stabilisationForce(const SphSnapshot& s, const Particles& pa, std::size_t i, std::size_t j,
                   const Vec3& x_j, const Vec3& v_j, const Mat3& R_j, const Vec3& g,
                   const SphControls& ctl, double& mu, const double* ratio = nullptr) {
  const Vec3 r_ij = s.x[i] - x_j;
  const double h_ij = 0.5 * (s.h[i] + s.h[j]);
  Vec3 f = Vec3::Zero();
  if (s.tensile[i] || s.tensile[j]) {
    const double fn = ratio ? *ratio
                            : stressRatio(r_ij.norm(), 0.5 * (s.d[i] + s.d[j]), h_ij,
                                          ctl.as_exponent);
    f = scaledSumTimes(s.V[i] * s.V[j] * fn, s.R[i], R_j, g);
  }
  mu = 0;
  const double vr = (s.v[i] - v_j).dot(r_ij);
  if (vr < 0) {
    const double mu_ij = h_ij * vr / (r_ij.squaredNorm() + 0.01 * h_ij * h_ij);
    const double c_ij = 0.5 * (s.c[i] + s.c[j]);
    const double rho_ij = 0.5 * (s.rho[i] + s.rho[j]);
    const double Pi = (-ctl.av_alpha * c_ij * mu_ij + ctl.av_beta * mu_ij * mu_ij) / rho_ij;
    f -= (pa.m[i] * pa.m[j] * Pi) * g;
    mu = -mu_ij;
  }
  return f;
}

/// The artificial stress's f^n of row i's pairs in the configuration `s`, into `ratio` (by
/// position in the row) wherever i or j is in tension, two pairs at a time: stabilisationForce's
/// arithmetic lane by lane, so the same bits. A pair's chain (square root, division, shape,
/// division, power) is long; two side by side take one chain's time (docs/performance-history.md,
/// forty-fifth session).
void pairStressRatios(const SphSnapshot& s, std::size_t i, const NeighbourList& nb, int exponent,
                      std::vector<double>& ratio) {
  const std::size_t begin = nb.offset[i], end = nb.offset[i + 1];
  ratio.resize(end - begin);
  for (std::size_t k = begin; k < end; k += 2) {
    const std::size_t k1 = std::min(k + 1, end - 1);  // an odd row's last pair fills both lanes
    const std::size_t j0 = static_cast<std::size_t>(nb.index[k]);
    const std::size_t j1 = static_cast<std::size_t>(nb.index[k1]);
    if (!(s.tensile[i] || s.tensile[j0] || s.tensile[j1])) continue;
    const Lanes2 r = norms(s.x[i] - s.x[j0], s.x[i] - s.x[j1]);
    const Lanes2 dp = {0.5 * (s.d[i] + s.d[j0]), 0.5 * (s.d[i] + s.d[j1])};
    const Lanes2 h = {0.5 * (s.h[i] + s.h[j0]), 0.5 * (s.h[i] + s.h[j1])};
    const Lanes2 fn = stressRatio(r, dp, h, exponent);
    ratio[k - begin] = fn[0];
    ratio[k1 - begin] = fn[1];
  }
}

/// Pass 3 for particle i: f_i = sum_j f_ij with
///   f_ij = V_i V_j (sigma_i B_i + sigma_j B_j) grad W_ij + stabilisation,
/// the first term the exact virtual-work dual of L_i (f_ij = -f_ji bit for bit, and the
/// internal power equals the stress power). Sets the stable step estimate. Returns the heat of
/// the stabilisation forces over the last interval (J): their work on the relative velocity
/// v^{n-1/2}, trapezoidal over the forces of this and the last step, half to each particle.
double forces(Model& model, std::size_t i, double dt, SphWorkspace& ws) {
  Particles& pa = model.particles;
  const SphControls& ctl = ws.controls;
  const NeighbourList& nb = ws.neighbours;
  const SphSnapshot& cur = ws.current;
  const SphSnapshot& prev = ws.previous;
  const std::size_t np = prev.size();
  const Mat3& Si = ws.stress_b[i];
  Vec3 f = Vec3::Zero();
  double heat_power = 0, mu_max = 0, mu = 0;
  thread_local std::vector<double> ratio;
  pairStressRatios(cur, i, nb, ctl.as_exponent, ratio);
  for (std::size_t k = nb.offset[i]; k < nb.offset[i + 1]; ++k) {
    const std::size_t j = static_cast<std::size_t>(nb.index[k]);
    const Vec3& g = ws.pair_grad[k];
    const Vec3 f_stab = stabilisationForce(cur, pa, i, j, cur.x[j], cur.v[j], cur.R[j], g, ctl,
                                           mu, &ratio[k - nb.offset[i]]);
    ws.pair_stab[k] = f_stab;
    mu_max = std::max(mu_max, mu);
    f += scaledSumTimes(cur.V[i] * cur.V[j], Si, ws.stress_b[j], g) + f_stab;
    Vec3 f_stab_sum = f_stab;
    if (i < np && j < np) {
      // the last step computed this pair's force in the previous configuration already
      const std::uint32_t kl = ws.pair_last_slot[k];
      f_stab_sum += kl != SphWorkspace::kNoLastPair
                        ? ws.pair_stab_last[kl]
                        : stabilisationForce(prev, pa, i, j, prev.x[j], prev.v[j], prev.R[j],
                                             previousGradient(prev, i, j), ctl, mu);
    } else {
      f_stab_sum += f_stab;
    }
    heat_power -= 0.25 * f_stab_sum.dot(pa.v[i] - pa.v[j]);
  }
  // Mirror images: sigma_j B_j and R_j map as tensors (P T P). Each pair of i with an image
  // stands for two pairs of the full model, mirrors of each other; i's row holds one of them,
  // and its partner's row the other, so the heat is shared as for real pairs.
  for (const MirrorImage& mi : ws.mirrors) {
    const NeighbourList& ml = mi.neighbours;
    const Reflection& M = mi.map;
    for (std::size_t k = ml.offset[i]; k < ml.offset[i + 1]; ++k) {
      const std::size_t j = static_cast<std::size_t>(ml.index[k]);
      const Vec3& g = mi.grad[k];
      const Vec3 f_stab = stabilisationForce(cur, pa, i, j, M.point(cur.x[j]),
                                             M.vector(cur.v[j]), M.tensor(cur.R[j]), g, ctl, mu);
      mu_max = std::max(mu_max, mu);
      f += scaledSumTimes(cur.V[i] * cur.V[j], Si, M.tensor(ws.stress_b[j]), g) + f_stab;
      const Vec3 f_stab_sum =
          f_stab + (i < np && j < np
                        ? stabilisationForce(prev, pa, i, j, M.point(prev.x[j]),
                                             M.vector(prev.v[j]), M.tensor(prev.R[j]),
                                             mi.grad_prev[k], ctl, mu)
                        : f_stab);
      heat_power -= 0.25 * f_stab_sum.dot(pa.v[i] - M.vector(pa.v[j]));
    }
  }
  pa.f[i] = f;
  // A particle with no neighbour (debris flown apart from its body) feels no SPH force: no
  // wave of its own limits its step, only its travel, held to a fraction of h per step for
  // the neighbour and contact searches (at rest it sets no limit: h / 0 = inf).
  const double ci = cur.c[i];
  const double speed =
      neighbourCount(ws, i) == 0
          ? pa.v[i].norm()
          : ci + pa.v[i].norm() + 1.2 * (ctl.av_alpha * ci + ctl.av_beta * mu_max);
  pa.dt[i] = ctl.dt_factor * cur.h[i] / speed;
  return heat_power * dt;
}

}  // namespace

void restorePairStabilisation(Model& model) {
  SphWorkspace& ws = model.sph;
  const NeighbourList& nb = ws.neighbours;
  ws.pair_stab.assign(nb.pairs(), Vec3::Zero());
  const long rows = nb.offset.empty() ? 0 : static_cast<long>(nb.offset.size() - 1);
#pragma omp parallel for schedule(dynamic, 128)
  for (long i = 0; i < rows; ++i) {
    double mu = 0;
    for (std::size_t k = nb.offset[i]; k < nb.offset[i + 1]; ++k) {
      const std::size_t j = static_cast<std::size_t>(nb.index[k]);
      const SphSnapshot& s = ws.current;
      ws.pair_stab[k] = stabilisationForce(s, model.particles, static_cast<std::size_t>(i), j,
                                           s.x[j], s.v[j], s.R[j], ws.pair_grad[k],
                                           ws.controls, mu);
    }
  }
}

void SphSnapshot::resize(std::size_t n) {
  resizeSnug(x, n);
  resizeSnug(v, n);
  resizeSnug(h, n);
  resizeSnug(V, n);
  resizeSnug(volume_rate, n);
  resizeSnug(rho, n);
  resizeSnug(c, n);
  resizeSnug(d, n);
  resizeSnug(B, n);
  resizeSnug(R, n);
  resizeSnug(tensile, n);
}

void computeParticleForces(Model& model, double dt_last, SphWorkspace& ws) {
  Particles& pa = model.particles;
  const std::size_t n = pa.size();
  if (n == 0) return;
  std::swap(ws.current, ws.previous);
  std::swap(ws.neighbours, ws.neighbours_last);
  std::swap(ws.pair_grad, ws.pair_grad_last);
  std::swap(ws.pair_stab, ws.pair_stab_last);
  resizeWorkspace(ws, n);
  ws.search.sphNeighboursVerlet(pa.x, pa.h, pa.body, ws.controls.verlet_skin, ws.neighbours);
  if (ws.neighbours.pairs() >= SphWorkspace::kNoLastPair)  // hundreds of GB of pair arrays
    throw RunError("SPH neighbour list of " + std::to_string(ws.neighbours.pairs()) +
                   " pairs at t = " + seconds(model.time) + ": more than the 2^32 - 1 it can index");
  resizeSnug(ws.pair_grad, ws.neighbours.pairs());
  resizeSnug(ws.pair_stab, ws.neighbours.pairs());
  resizeSnug(ws.pair_last_slot, ws.neighbours.pairs());
  prepareMirrors(model, ws);
  for (std::size_t m = 0; m < ws.mirrors.size(); ++m) {
    MirrorImage& mi = ws.mirrors[m];
    ws.search.mirrorRowsVerlet(pa.x, pa.h, pa.body, mi.map, true, m, ws.controls.verlet_skin,
                               mi.neighbours);
    resizeSnug(mi.grad, mi.neighbours.pairs());
    resizeSnug(mi.grad_prev, mi.neighbours.pairs());
  }
  const long ni = static_cast<long>(n);

#pragma omp parallel for schedule(static)
  for (long i = 0; i < ni; ++i) predictVolume(model, static_cast<std::size_t>(i), dt_last, ws);
  // Rows differ in length (debris has few neighbours, the bulk ~75) and each particle writes
  // only its own entries: dynamic chunks balance the threads and change no result.
#pragma omp parallel for schedule(dynamic, 128)
  for (long i = 0; i < ni; ++i) kinematics(pa, static_cast<std::size_t>(i), ws);
  // Volumes of neighbours change below: the passes must stay separate.
#pragma omp parallel for schedule(dynamic, 128)
  for (long i = 0; i < ni; ++i) updateMaterial(model, static_cast<std::size_t>(i), dt_last, ws);
  // Stabilisation work becomes heat (no pass reads another particle's energy).
#pragma omp parallel for schedule(dynamic, 128)
  for (long i = 0; i < ni; ++i) {
    const double heat = forces(model, static_cast<std::size_t>(i), dt_last, ws);
    ws.av_work[i] = heat;
    pa.state[i].e += heat / pa.m[i];
    ws.internal_energy[i] = pa.m[i] * pa.state[i].e;
  }

  // Sums in a fixed order (same for any thread count), over contiguous arrays: read from the
  // particles' states (a cache line each), this serial loop took 0.6 % of the SPH step's
  // time on 2 threads, one thread waiting (docs/performance-history.md, twenty-sixth session).
  double internal = 0, plastic = 0, av = 0;
  for (std::size_t i = 0; i < n; ++i) {
    internal += ws.internal_energy[i];
    plastic += ws.plastic_work[i];
    av += ws.av_work[i];
  }
  EnergyBudget& en = model.energy;
  en.internal += internal;
  en.plastic_work += plastic;
  en.artificial_viscosity += av;
}

void computeParticleForces(Model& model, double dt_last) {
  computeParticleForces(model, dt_last, model.sph);
}

void enforceParticleContact(Model& model, double dt, SphWorkspace& ws) {
  Particles& pa = model.particles;
  const std::size_t n = pa.size();
  if (n == 0 || !(dt > 0)) return;
  if (std::all_of(pa.body.begin(), pa.body.end(), [&](int b) { return b == pa.body[0]; }))
    return;

  // Broad phase: pairs that can come within their contact distance during the step.
  resizeSnug(ws.contact_radius, n);
  resizeSnug(ws.contact_spacing, n);
#pragma omp parallel for schedule(static)
  for (std::size_t i = 0; i < n; ++i) {
    ws.contact_spacing[i] = std::cbrt(pa.V[i]);
    ws.contact_radius[i] = 0.5 * ws.contact_spacing[i] + dt * pa.v[i].norm();
  }
  // The pairs across bodies are few (interfaces only) and their radius is half a spacing:
  // a skin of 2 radii costs little filtering and lasts ~14 steps on the four-plate scene,
  // where 0.3 lasted ~2.4.
  constexpr double kContactVerletSkin = 2.0;
  ws.search.crossBodyPairsVerlet(pa.x, ws.contact_radius, pa.body, kContactVerletSkin,
                                 ws.contact_pairs);
  prepareMirrors(model, ws);
  for (std::size_t m = 0; m < ws.mirrors.size(); ++m)
    ws.search.mirrorRowsVerlet(pa.x, ws.contact_radius, pa.body, ws.mirrors[m].map, false, m,
                               kContactVerletSkin, ws.mirrors[m].contact);

  // Johnson-Stryk style kinematic correction, Gauss-Seidel over the pairs in a fixed order:
  // a pair that would end the step closer than (d_i + d_j)/2 gets the normal relative velocity
  // that lands it at that distance (or stops its approach if already closer), shared so that
  // momentum is conserved. Velocities only ever move apart: no pulling, no sticking. The work
  // of these corrections is booked by the solver (correctionWork), as for walls and ties.
  // i against j, or against the mirror image of j (`image`): then j takes the mirror of what
  // its image takes, as it does in the mirror pair (the image of i against j), which is the
  // same interaction and is not listed again.
  const auto correct = [&](int i, int j, const Reflection* image) {
    const Vec3 x_j = image ? image->point(pa.x[j]) : pa.x[j];
    const Vec3 v_j = image ? image->vector(pa.v[j]) : pa.v[j];
    const Vec3 r_ij = pa.x[i] - x_j;
    const double r = r_ij.norm();
    if (!(r > 0)) return;
    const Vec3 nrm = r_ij / r;
    const double gap = r - 0.5 * (ws.contact_spacing[i] + ws.contact_spacing[j]);
    const double vn = (pa.v[i] - v_j).dot(nrm);
    const double vn_min = gap > 0 ? -gap / dt : 0.0;
    if (vn >= vn_min) return;
    const double mi = pa.m[i], mj = pa.m[j];
    const double impulse = (vn_min - vn) * mi * mj / (mi + mj);
    pa.v[i] += (impulse / mi) * nrm;
    pa.v[j] -= (impulse / mj) * (image ? image->vector(nrm) : nrm);
  };
  for (int pass = 0; pass < ws.controls.contact_passes; ++pass) {
    for (const auto& [i, j] : ws.contact_pairs) correct(i, j, nullptr);
    for (const MirrorImage& mi : ws.mirrors)
      for (std::size_t i = 0; i + 1 < mi.contact.offset.size(); ++i)
        for (std::size_t k = mi.contact.offset[i]; k < mi.contact.offset[i + 1]; ++k)
          correct(static_cast<int>(i), mi.contact.index[k], &mi.map);
  }
}

void enforceParticleContact(Model& model, double dt) {
  enforceParticleContact(model, dt, model.sph);
}

}  // namespace fesph
