// SPDX-License-Identifier: MIT
// Johnson-Cook failure strain, the denominator of the damage sum D = sum(d eps_p / eps_f).
#include "core/material/material.hpp"

#include <cmath>
#include <limits>

namespace fesph {

namespace {

/// Lower bound of eps_f. Some fits (Armco iron: D1 = -2.20) go negative at high triaxiality;
/// there the point fails on its first plastic increment instead of healing (negative dD).
/// Same role as EFMIN of LS-DYNA MAT_015.
constexpr double kMinFailureStrain = 1e-6;

}  // namespace

/// Johnson & Cook 1985 (Eng. Fract. Mech. 21:31), eq. 1:
///   eps_f = [D1 + D2 exp(D3 sigma*)] (1 + D4 ln eps_dot*) (1 + D5 T*)   (-)
/// sigma* = -p / sigma_eq (triaxiality, p positive in compression), eps_dot* = max(1,
/// eps_dot/eps_dot0) with eps_dot in 1/s, T* the homologous temperature. Sign convention: D3 < 0
/// makes eps_f fall as triaxiality rises. +infinity when the material has no damage model.
double failureStrain(const Material& mat, double triaxiality, double eps_dot, double T) {
  if (!mat.damage) return std::numeric_limits<double>::infinity();
  // D2 = 0 would make 0 * exp(overflow) a NaN under extreme compression.
  const double stress = mat.D1 + (mat.D2 != 0.0 ? mat.D2 * std::exp(mat.D3 * triaxiality) : 0.0);
  const double eps_f = stress * (1.0 + mat.D4 * logRateRatio(mat, eps_dot)) *
                       (1.0 + mat.D5 * homologousTemperature(mat, T));
  return eps_f > kMinFailureStrain ? eps_f : kMinFailureStrain;
}

}  // namespace fesph
