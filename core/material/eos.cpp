// SPDX-License-Identifier: MIT
// Equations of state (pressure positive in compression) and the longitudinal wave speed that
// bounds the explicit time step.
#include "core/material/material.hpp"

#include "core/common/lanes.hpp"

#include <algorithm>
#include <cmath>

namespace fesph {

namespace {

/// The Hugoniot p_H = rho0 c0^2 eta / (1 - s eta)^2 has a pole at eta = 1/s (rho/rho0 = 1 + 1/(s-1),
/// about 3 for steel). Compression is clamped where 1 - s eta = 0.1, i.e. at most 100 rho0 c0^2
/// eta (~10 TPa for steel, far above the ~25 GPa of the 1300 m/s scenes), so the pressure stays
/// finite and only a collapsing element ever reaches the clamp.
constexpr double kMinHugoniotDenominator = 0.1;

double clampCompression(const Material& mat, double eta) {
  return mat.s > 0.0 ? std::min(eta, (1.0 - kMinHugoniotDenominator) / mat.s) : eta;
}

}  // namespace

/// Linear:  p = K mu, mu = rho/rho0 - 1 (K bulk modulus, Pa); energy plays no part.
/// Mie-Grueneisen with a shock Hugoniot reference (us = c0 + s up; Steinberg 1996,
/// UCRL-MA-106439; Meyers 1994, Dynamic Behavior of Materials, ch. 4), eta = 1 - rho0/rho:
///   eta > 0:  p_H = rho0 c0^2 eta / (1 - s eta)^2,  e_H = p_H eta / (2 rho0),
///             p = p_H + Gamma0 rho0 (e - e_H)
///   eta <= 0: p = rho0 c0^2 eta + Gamma0 rho0 e
/// with Gamma rho = Gamma0 rho0 held constant. p in Pa, rho in kg/m^3, e in J/kg.
/// A fully damaged point (damage >= 1) takes no tension: p < 0 becomes 0.
///
/// c_L^2 = (K_t + 4G/3) / rho (m^2/s^2). K_t is the bulk tangent: K for the linear EOS; for
/// Mie-Grueneisen rho0 c0^2 (1 + s eta)/(1 - s eta)^3 = d p_H / d eta, at least rho0 c0^2.
/// On the Hugoniot this is above the isentropic sound speed (by 3% at eta = 0.05, 7% at 0.1,
/// 17% at 0.2 for steel), so it is a safe upper estimate for the explicit time step.
// Two densities side by side (Lanes2), each lane the operations of one density in their
// order: the Hugoniot terms are formed in both lanes and kept where the lane is compressed.
std::array<EosAtDensity, 2> eosAtDensities(const Material& mat, double rho_a, double rho_b) {
  const Lanes2 rho = {rho_a, rho_b};
  std::array<EosAtDensity, 2> at;
  if (mat.eos == EosModel::Linear) {
    const Lanes2 p_ref = mat.K * (rho / mat.rho0 - 1.0);
    const Lanes2 c2 = (mat.K + 4.0 * mat.G / 3.0) / rho;
    for (int l = 0; l < 2; ++l) {
      at[l].p_ref = p_ref[l];
      at[l].wave_speed_sq = c2[l];
    }
    return at;
  }
  const Lanes2 eta_raw = 1.0 - mat.rho0 / rho;
  const Lanes2 eta = {clampCompression(mat, eta_raw[0]), clampCompression(mat, eta_raw[1])};
  const double rc2 = mat.rho0 * mat.c0 * mat.c0;
  const Lanes2 den = 1.0 - mat.s * eta;
  const Lanes2 p_hugoniot = rc2 * eta / (den * den);
  const Lanes2 e_hugoniot = p_hugoniot * eta / (2.0 * mat.rho0);
  // the tangent is taken at least at rho0
  const Lanes2 eta_t = {std::max(0.0, eta[0]), std::max(0.0, eta[1])};
  const Lanes2 den_t = 1.0 - mat.s * eta_t;
  const Lanes2 Kt = rc2 * (1.0 + mat.s * eta_t) / (den_t * den_t * den_t);
  const Lanes2 c2 = (Kt + 4.0 * mat.G / 3.0) / rho;
  for (int l = 0; l < 2; ++l) {
    if (eta[l] > 0.0) {
      at[l].branch = EosAtDensity::Branch::Compressed;
      at[l].p_ref = p_hugoniot[l];
      at[l].e_ref = e_hugoniot[l];
    } else {
      at[l].branch = EosAtDensity::Branch::Expanded;
      at[l].p_ref = rc2 * eta[l];
    }
    at[l].wave_speed_sq = c2[l];
  }
  return at;
}

EosAtDensity eosAtDensity(const Material& mat, double rho) {
  return eosAtDensities(mat, rho, rho)[0];
}

double eosPressure(const Material& mat, double rho, double e, double damage) {
  return eosAtDensity(mat, rho).pressure(mat, e, damage);
}

double waveSpeedSquared(const Material& mat, double rho) {
  return eosAtDensity(mat, rho).wave_speed_sq;
}

double waveSpeed(const Material& mat, double rho) { return std::sqrt(waveSpeedSquared(mat, rho)); }

}  // namespace fesph
