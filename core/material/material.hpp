// SPDX-License-Identifier: MIT
// Material parameters (SI units) and the one material-point update shared by tetrahedra and
// SPH particles: hypoelastic Jaumann-rate deviatoric stress, Johnson-Cook radial return with
// adiabatic heating, Johnson-Cook damage, and the pressure from a linear or Mie-Grueneisen EOS.
#pragma once

#include "core/common/types.hpp"

#include <algorithm>
#include <array>
#include <cstddef>
#include <limits>
#include <string>

namespace fesph {

enum class StrengthModel { Elastic, JohnsonCook };
enum class EosModel { Linear, MieGruneisen };

/// Constants of one material. Every number in the library records its source.
struct Material {
  std::string name;
  std::string source;  ///< where the numbers come from
  std::string status;  ///< "published", "stand-in" or "assumption"

  // elastic and thermal
  double rho0 = 0;        ///< reference density, kg/m^3
  double E = 0;           ///< Young's modulus, Pa
  double nu = 0;          ///< Poisson's ratio, -
  double G = 0;           ///< shear modulus, Pa (derived: E / (2(1+nu)))
  double K = 0;           ///< bulk modulus, Pa (derived: E / (3(1-2nu)))
  double cp = 0;          ///< specific heat, J/(kg K)
  double T_room = 293.0;  ///< reference (room) temperature, K
  double T_melt = 0;      ///< melting temperature, K (<= T_room disables thermal softening)
  double taylor_quinney = 0.9;  ///< fraction of plastic work turned into heat, -

  // strength: sigma_y = (A + B eps_p^n)(1 + C ln eps_dot*)(1 - T*^m), eps_dot* = max(1, eps_dot/eps_dot0)
  StrengthModel strength = StrengthModel::Elastic;
  double A = 0, B = 0, n = 1, C = 0, m = 1;  ///< Pa, Pa, -, -, -
  double eps_dot0 = 1.0;                     ///< reference strain rate, 1/s

  // Johnson-Cook failure: eps_f = [D1 + D2 exp(D3 sigma*)](1 + D4 ln eps_dot*)(1 + D5 T*)
  bool damage = false;  ///< accumulate damage at all
  double D1 = 0, D2 = 0, D3 = 0, D4 = 0, D5 = 0;

  // equation of state
  EosModel eos = EosModel::Linear;
  double c0 = 0;      ///< bulk sound speed, m/s (Mie-Grueneisen us = c0 + s up)
  double s = 0;       ///< Hugoniot slope, -
  double gamma0 = 0;  ///< Grueneisen coefficient, -

  // element erosion (plain-FEM baseline): delete an element at this eps_p (<= 0: never)
  double erosion_strain = 0;
};

/// Fill the derived constants (G, K) and check that the numbers are physically possible.
/// Returns an empty string when the material is valid, otherwise what is wrong.
std::string finaliseMaterial(Material& mat);

/// finaliseMaterial that also names, in `key`, the library key of the offending value
/// ("density", "johnson_cook.n", "eos.c0", ...; empty when valid), so that a loader can point
/// at the line that holds it.
std::string finaliseMaterial(Material& mat, std::string& key);

/// Homologous temperature T* = (T - T_room) / (T_melt - T_room) clamped to [0, 1]; 0 when
/// thermal softening is off (T_melt <= T_room). Shared by flow stress and failure strain.
double homologousTemperature(const Material& mat, double T);

/// ln(eps_dot*) with eps_dot* = max(1, eps_dot / eps_dot0): rates below the reference rate
/// neither soften nor weaken (the Johnson-Cook fits hold only above it).
double logRateRatio(const Material& mat, double eps_dot);

/// History of one material point (an element or a particle).
struct PointState {
  Sym s;                ///< deviatoric Cauchy stress, Pa
  double p = 0;         ///< pressure (positive in compression), Pa
  double eps_p = 0;     ///< equivalent plastic strain, -
  double eps_rate = 0;  ///< equivalent plastic strain rate, 1/s
  double T = 293.0;     ///< temperature, K
  double e = 0;         ///< specific internal energy, J/kg
  double damage = 0;    ///< Johnson-Cook damage, 0..1
};

/// Johnson-Cook flow stress (Pa) at plastic strain eps_p, equivalent strain rate eps_dot (1/s)
/// and temperature T (K). Johnson & Cook 1983.
double flowStress(const Material& mat, double eps_p, double eps_dot, double T);

/// Johnson-Cook failure strain at triaxiality sigma* = -p / sigma_eq, strain rate and T.
/// Johnson & Cook 1985.
double failureStrain(const Material& mat, double triaxiality, double eps_dot, double T);

/// EOS pressure (Pa) at density rho (kg/m^3) and specific internal energy e (J/kg).
/// A fully damaged point (damage >= 1) carries no tension: negative pressure is cut to 0.
double eosPressure(const Material& mat, double rho, double e, double damage = 0.0);

/// Longitudinal (bulk + 4/3 shear) wave speed at density rho, m/s. Used by the time step.
double waveSpeed(const Material& mat, double rho);
/// Its square, m^2/s^2: blends of wave speeds are taken on c^2, without two square roots.
double waveSpeedSquared(const Material& mat, double rho);

/// The EOS at one density: the terms of eosPressure that do not depend on the energy, and
/// waveSpeedSquared, each taken once for a point's predictor and corrector pressures (their
/// divisions were most of those calls). The same bits as eosPressure and waveSpeedSquared.
struct EosAtDensity {
  enum class Branch { Linear, Compressed, Expanded };
  Branch branch = Branch::Linear;
  double p_ref = 0;          ///< Pa: K mu (linear), p_H (compressed), rho0 c0^2 eta (expanded)
  double e_ref = 0;          ///< J/kg: e_H on the Hugoniot (compressed)
  double wave_speed_sq = 0;  ///< waveSpeedSquared, m^2/s^2
  /// eosPressure at specific internal energy e (J/kg).
  double pressure(const Material& mat, double e, double damage) const {
    double p = p_ref;
    if (branch == Branch::Compressed) p = p_ref + mat.gamma0 * mat.rho0 * (e - e_ref);
    if (branch == Branch::Expanded) p = p_ref + mat.gamma0 * mat.rho0 * e;
    return damage >= 1.0 ? std::max(p, 0.0) : p;
  }
};
EosAtDensity eosAtDensity(const Material& mat, double rho);
/// eosAtDensity at two densities at once, each with its bits: the two share the divider (an
/// element's own density and its nodes' average, ANP, take ten divisions one by one).
std::array<EosAtDensity, 2> eosAtDensities(const Material& mat, double rho_a, double rho_b);

/// The two costly factors of a point's quasi-static flow stress, kept from step to step: the
/// thermal factor 1 - T*^m at temperature T and the hardening A + B eps_p^n at plastic strain
/// eps_p, a pow each. An entry holds while its keys equal the point's material and T or eps_p
/// (NaN: none yet), so it never gives another value than the pow would: a point that does not
/// yield keeps both, one that yields keeps the hardening its return last evaluated (at the new
/// eps_p).
struct YieldCache {
  const Material* mat = nullptr;
  double T = std::numeric_limits<double>::quiet_NaN();
  double thermal = 1;
  double eps_p = std::numeric_limits<double>::quiet_NaN();
  double hardening = 0;
};

/// A point whose elastic trial stress lies outside the yield surface, between its trial
/// (trialDeviatoricStress) and its radial return (completeReturns).
struct PendingReturn {
  const Material* mat = nullptr;
  PointState* st = nullptr;     ///< st->s holds the trial stress
  YieldCache* cache = nullptr;  ///< the point's, if it keeps one
  double dt = 0;                ///< s
  double rho = 0;               ///< density at the start of the step, kg/m^3
  double sigma_eq_tr = 0;       ///< von Mises of the trial stress, Pa
  double thermal = 1;           ///< 1 - T*^m at the start of the step
  double sigma_y0 = 0;          ///< quasi-static flow stress at the start of the step, Pa
  double guess = 0;             ///< Newton's start: the last plastic increment
  double work = 0;              ///< out: plastic work over the step, J/m^3
};

/// The first half of updateDeviatoricStress: Jaumann rotation and elastic trial (st.s becomes
/// the trial stress). Returns true when the point yields; `r` then holds what its return needs.
/// `cache` (optional) keeps the flow stress's thermal factor and hardening between steps.
bool trialDeviatoricStress(const Material& mat, const Sym& D, const Mat3& W, double dt,
                           double rho, PointState& st, PendingReturn& r,
                           YieldCache* cache = nullptr);

/// trialDeviatoricStress from its trial stress s_tr = s + dt (W s - s W) + 2 G dt dev(D) and
/// von Mises equivalent, computed by the caller (the element pass takes four points at once).
bool yieldsAtTrial(const Material& mat, const Sym& s_tr, double sigma_eq_tr, double dt,
                   double rho, PointState& st, PendingReturn& r, YieldCache* cache);

/// The second half for `count` yielding points: radial return, heating, damage, and r[k].work.
/// Several points are iterated side by side, so the processor overlaps one point's pow and log
/// with another's; each point takes the same operations as alone (the same bits).
void completeReturns(PendingReturn* r, std::size_t count);

/// Advance the deviatoric stress of one point over dt: Jaumann rotation by the spin W,
/// elastic trial with the deviatoric rate of deformation, Johnson-Cook radial return,
/// adiabatic heating and damage accumulation (using the pressure in `st.p`).
/// D: rate of deformation (1/s); W: spin (1/s); rho: current density.
/// Returns the plastic work per unit volume done over the step (J/m^3).
double updateDeviatoricStress(const Material& mat, const Sym& D, const Mat3& W, double dt,
                              double rho, PointState& st, YieldCache* cache = nullptr);

}  // namespace fesph
