// SPDX-License-Identifier: MIT
// Equations of state (pressure positive in compression) and the longitudinal wave speed that
// bounds the explicit time step.
#include "core/material/material.hpp"

#include "core/common/lanes.hpp"
#include "core/material/eos_lanes.hpp"

#include <algorithm>
#include <cmath>

namespace fesph {

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
// Two densities side by side (Lanes2, eos_lanes.hpp), each lane the operations of one density.
std::array<EosAtDensity, 2> eosAtDensities(const Material& mat, double rho_a, double rho_b) {
  const EosLanes<Lanes2> lanes = eosLanes(mat, Lanes2{rho_a, rho_b});
  std::array<EosAtDensity, 2> at;
  for (int l = 0; l < 2; ++l) {
    if (mat.eos != EosModel::Linear)
      at[l].branch = lanes.compressed[l] ? EosAtDensity::Branch::Compressed
                                         : EosAtDensity::Branch::Expanded;
    at[l].p_ref = lanes.p_ref[l];
    at[l].e_ref = lanes.e_ref[l];
    at[l].wave_speed_sq = lanes.wave_speed_sq[l];
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
