// SPDX-License-Identifier: MIT
// Johnson-Cook flow stress and the deviatoric stress update of one material point: Jaumann
// rotation, elastic trial, radial return, adiabatic heating and damage accumulation.
#include "core/material/material.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <optional>

namespace fesph {

double homologousTemperature(const Material& mat, double T) {
  if (mat.T_melt <= mat.T_room) return 0.0;
  return std::clamp((T - mat.T_room) / (mat.T_melt - mat.T_room), 0.0, 1.0);
}

double logRateRatio(const Material& mat, double eps_dot) {
  const double ratio = eps_dot / mat.eps_dot0;
  return ratio > 1.0 ? std::log(ratio) : 0.0;  // log(max(1, ratio)) without the log of 1
}

namespace {

/// The thermal factor 1 - T*^m of the flow stress.
double thermalFactor(const Material& mat, double T) {
  const double Ts = homologousTemperature(mat, T);
  return Ts > 0.0 ? 1.0 - std::pow(Ts, mat.m) : 1.0;
}

/// The hardening A + B eps_p^n of the flow stress (a negative eps_p counts as 0).
double hardeningAt(const Material& mat, double eps_p) {
  const double ep = std::max(eps_p, 0.0);
  return mat.A + (ep > 0.0 ? mat.B * std::pow(ep, mat.n) : 0.0);
}

/// flowStress with its hardening and thermal factor given.
double flowStressAt(const Material& mat, double hardening, double eps_dot, double thermal) {
  if (mat.strength == StrengthModel::Elastic) return std::numeric_limits<double>::infinity();
  const double rate = 1.0 + mat.C * logRateRatio(mat, eps_dot);
  return hardening * rate * thermal;
}

}  // namespace

/// Johnson & Cook 1983 (7th Int. Symp. Ballistics, The Hague), eq. 1:
///   sigma_y = (A + B eps_p^n)(1 + C ln eps_dot*)(1 - T*^m)   [Pa]
/// eps_p plastic strain (-), eps_dot equivalent strain rate (1/s), T temperature (K);
/// eps_dot* = max(1, eps_dot/eps_dot0), T* = homologousTemperature in [0, 1].
/// The elastic strength model never yields: its flow stress is +infinity.
double flowStress(const Material& mat, double eps_p, double eps_dot, double T) {
  return flowStressAt(mat, hardeningAt(mat, eps_p), eps_dot, thermalFactor(mat, T));
}

namespace {

/// W s - s W for a spin W (antisymmetric) and a symmetric s: with M = W s, s W = -M^T, so
/// the rotation is M + M^T, and only M is formed (same bits as the two full products).
Sym jaumannRate(const Mat3& W, const Sym& s) {
  const Mat3 M = W * s.matrix();
  return {2.0 * M(0, 0), 2.0 * M(1, 1), 2.0 * M(2, 2), M(0, 1) + M(1, 0), M(1, 2) + M(2, 1),
          M(2, 0) + M(0, 2)};
}

/// Flow stress at the end of a plastic increment dlam taken over dt: the strain is eps_p + dlam
/// and the rate is the plastic strain rate dlam / dt (Johnson & Cook 1983 define eps_dot* with
/// the equivalent plastic strain rate). dt <= 0: quasi-static. `slope` (if not null) receives
/// d sigma_y / d dlam (Pa): the hardening slope times the rate factor plus the hardening times
/// the slope of the rate factor, C / dlam above the reference rate; +infinity at
/// eps_p + dlam = 0 when n < 1. `thermal` is 1 - T*^m, fixed during a return (T is the
/// temperature at its start), so evaluated once by the caller; the strain and rate terms are
/// shared by the stress and its slope: one pow and one log fewer per Newton iteration.
/// `hardening_out` (if not null) receives A + B (eps_p + dlam)^n, hardeningAt's value there.
double flowStressAfter(const Material& mat, double eps_p, double dlam, double dt,
                       double thermal, double* slope, double* hardening_out) {
  const double ep = std::max(eps_p + dlam, 0.0);
  const double rate = dt > 0.0 ? dlam / dt : 0.0;
  const double rate_factor = 1.0 + mat.C * logRateRatio(mat, rate);
  const double ep_n = ep > 0.0 ? std::pow(ep, mat.n) : 0.0;
  const double hardening = mat.A + mat.B * ep_n;
  if (hardening_out) *hardening_out = hardening;
  if (slope) {
    double dh;
    if (mat.B == 0.0)
      dh = 0.0;
    else if (ep > 0.0)
      dh = mat.B * mat.n * ep_n / ep;  // n B ep^(n-1) from the ep^n already taken
    else
      dh = mat.n < 1.0 ? std::numeric_limits<double>::infinity() : (mat.n == 1.0 ? mat.B : 0.0);
    const double rate_slope = rate > mat.eps_dot0 && dlam > 0.0 ? mat.C / dlam : 0.0;
    *slope = (dh * rate_factor + hardening * rate_slope) * thermal;
  }
  return hardening * rate_factor * thermal;
}

/// Plastic multiplier dlam of the radial return: the root of
///   g(dlam) = sigma_eq_tr - 3 G dlam - sigma_y(eps_p + dlam, dlam / dt) = 0.
/// The rate term makes the return implicit in the rate, as the viscoplastic form of JC. g is
/// strictly decreasing (sigma_y grows with both its strain and its rate), g(0) > 0 and
/// g(hi) <= 0 for hi = (sigma_eq_tr - sigma_y(eps_p, 0))/(3G), so Newton is run inside the
/// bracket [0, hi] and falls back to bisection when its step leaves the bracket, e.g. at the
/// infinite slope of n < 1 hardening at eps_p = 0 or of the rate term at the reference rate.
/// Newton starts from the point's last plastic increment (its plastic rate times dt) when that
/// lies inside the bracket, else from hi: in steady flow the guess is nearly the root
/// (BM_ElementKernel: 2.2 evaluations per return against 4.0 from hi).
/// One object per point, advanced one iteration at a time (`iterate`), so that several
/// points' iterations can be interleaved (completeReturns).
class RadialReturn {
 public:
  explicit RadialReturn(const PendingReturn& r)
      : r_(r), G3_(3.0 * r.mat->G), hi_((r.sigma_eq_tr - r.sigma_y0) / G3_) {
    x_ = (r.guess > 0.0 && r.guess < hi_) ? r.guess : hi_;
  }
  bool done() const { return done_; }
  double dlam() const { return x_; }
  double sigmaY() const { return sigma_y_; }  ///< the flow stress at dlam
  double hardening() const { return hardening_; }  ///< A + B (eps_p + dlam)^n

  /// One Newton (or bisection) iteration; done() once converged or after 200 iterations.
  void iterate() {
    const Material& mat = *r_.mat;
    const PointState& st = *r_.st;
    double slope = 0;
    const double sy = flowStressAfter(mat, st.eps_p, x_, r_.dt, r_.thermal, &slope, &hardening_);
    const double g = r_.sigma_eq_tr - G3_ * x_ - sy;
    // 1e-10 sigma_y is 100x inside the 1e-8 promised; the second term is round-off in g.
    if (std::abs(g) <= 1e-10 * sy + 1e-14 * r_.sigma_eq_tr) return finish(sy);
    (g > 0.0 ? lo_ : hi_) = x_;
    const double xn = x_ + g / (G3_ + slope);
    x_ = (xn > lo_ && xn < hi_) ? xn : 0.5 * (lo_ + hi_);
    // bracket at round-off: x is the root
    if (hi_ - lo_ <= 4e-16 * hi_ || ++iterations_ == 200)
      finish(flowStressAfter(mat, st.eps_p, x_, r_.dt, r_.thermal, nullptr, &hardening_));
  }

 private:
  void finish(double sigma_y) {
    sigma_y_ = sigma_y;
    done_ = true;
  }

  const PendingReturn& r_;
  double G3_, lo_ = 0.0, hi_, x_;
  double sigma_y_ = 0, hardening_ = 0;
  int iterations_ = 0;
  bool done_ = false;
};

/// After the return: the stress scaled back to the surface, the plastic strain and rate,
/// adiabatic heating and damage (using the pressure in st.p). Sets r.work, and keeps the
/// hardening at the new plastic strain in the point's cache.
void applyReturn(PendingReturn& r, double dlam, double sigma_y, double hardening) {
  const Material& mat = *r.mat;
  PointState& st = *r.st;
  const double dt = r.dt;
  const double rate = dt > 0.0 ? dlam / dt : 0.0;
  st.s = st.s * (1.0 - 3.0 * mat.G * dlam / r.sigma_eq_tr);
  const double T0 = st.T;
  st.eps_p += dlam;
  if (r.cache) {
    r.cache->eps_p = st.eps_p;
    r.cache->hardening = hardening;
  }
  if (dt > 0.0) st.eps_rate = dlam / dt;

  r.work = sigma_y * dlam;
  if (mat.cp > 0.0) st.T += mat.taylor_quinney * r.work / (r.rho * mat.cp);

  if (mat.damage) {
    // sigma_eq = sigma_y after the return; a melted point (sigma_y = 0) counts as sigma* = 0.
    const double triaxiality = sigma_y > 0.0 ? -st.p / sigma_y : 0.0;
    st.damage = std::min(1.0, st.damage + dlam / failureStrain(mat, triaxiality, rate, T0));
    if (st.damage >= 1.0) st.s = Sym{};
  }
}

}  // namespace

/// Hypoelastic-plastic update (Wilkins 1964 radial return; Simo & Hughes 1998, Box 3.2):
///   Jaumann:  s += dt (W s - s W)                         (objective rotation, first order)
///   trial:    s_tr = s + 2 G dt dev(D)
///   return:   s = s_tr (1 - 3 G dlam / sigma_eq_tr), sigma_eq = sigma_y(eps_p + dlam)
/// The rate in the C term is the equivalent plastic strain rate dlam / dt of the step, as in
/// Johnson & Cook 1983 (eps_dot* = eps_dot_p / eps_dot0), solved with the return; T is the
/// temperature at the start of the step. A point that does not yield sees the quasi-static
/// surface. Heating dT = chi sigma_y dlam / (rho cp) (K); damage dD = dlam / eps_f(-p/sigma_eq,
/// dlam/dt, T) (Johnson & Cook 1985), capped at 1.
/// This function takes the first two steps; completeReturns the third and the rest.
bool trialDeviatoricStress(const Material& mat, const Sym& D, const Mat3& W, double dt,
                           double rho, PointState& st, PendingReturn& r, YieldCache* cache) {
  const Sym s_tr = st.s + jaumannRate(W, st.s) * dt + D.deviator() * (2.0 * mat.G * dt);
  return yieldsAtTrial(mat, s_tr, vonMises(s_tr), dt, rho, st, r, cache);
}

bool yieldsAtTrial(const Material& mat, const Sym& s_tr, double sigma_eq_tr, double dt,
                   double rho, PointState& st, PendingReturn& r, YieldCache* cache) {
  const double guess = st.eps_rate * dt;
  st.eps_rate = 0.0;
  if (st.damage >= 1.0) {  // a failed point carries no deviatoric stress
    st.s = Sym{};
    return false;
  }
  st.s = s_tr;

  // Inside the quasi-static yield surface: elastic. Always so for the Elastic model.
  if (mat.strength == StrengthModel::Elastic) return false;
  YieldCache fresh;
  YieldCache& c = cache ? *cache : fresh;
  if (c.mat != &mat) c = YieldCache{&mat};
  if (!(c.T == st.T)) {
    c.T = st.T;
    c.thermal = thermalFactor(mat, st.T);
  }
  if (!(c.eps_p == st.eps_p)) {
    c.eps_p = st.eps_p;
    c.hardening = hardeningAt(mat, st.eps_p);
  }
  const double sigma_y0 = flowStressAt(mat, c.hardening, 0.0, c.thermal);
  if (sigma_eq_tr <= sigma_y0) return false;
  r = PendingReturn{&mat, &st, cache, dt, rho, sigma_eq_tr, c.thermal, sigma_y0, guess, 0.0};
  return true;
}

void completeReturns(PendingReturn* r, std::size_t count) {
  // Each return is a chain of dependent pow and log calls (latency ~3x their throughput
  // here): kLanes independent chains side by side keep the processor busy.
  constexpr std::size_t kLanes = 8;
  for (std::size_t b = 0; b < count; b += kLanes) {
    const std::size_t lanes = std::min(kLanes, count - b);
    std::array<std::optional<RadialReturn>, kLanes> ret;
    for (std::size_t k = 0; k < lanes; ++k) ret[k].emplace(r[b + k]);
    for (bool running = true; running;) {
      running = false;
      for (std::size_t k = 0; k < lanes; ++k) {
        if (ret[k]->done()) continue;
        ret[k]->iterate();
        running = running || !ret[k]->done();
      }
    }
    for (std::size_t k = 0; k < lanes; ++k)
      applyReturn(r[b + k], ret[k]->dlam(), ret[k]->sigmaY(), ret[k]->hardening());
  }
}

/// Returns the plastic work per unit volume (J/m^3).
double updateDeviatoricStress(const Material& mat, const Sym& D, const Mat3& W, double dt,
                              double rho, PointState& st, YieldCache* cache) {
  PendingReturn r;
  if (!trialDeviatoricStress(mat, D, W, dt, rho, st, r, cache)) return 0.0;
  completeReturns(&r, 1);
  return r.work;
}

}  // namespace fesph
