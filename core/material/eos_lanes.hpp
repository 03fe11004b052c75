// SPDX-License-Identifier: MIT
// The EOS terms that do not depend on the energy (EosAtDensity) for several densities side by
// side, one density a lane of a GCC vector (Lanes2 in eosAtDensities, four elements' in the
// element pass C). Each lane takes the scalar formulas' operations in their order; the
// compressed and expanded branches are taken in every lane and selected, so each lane has the
// bits one density alone would get.
#pragma once

#include "core/material/material.hpp"

namespace fesph {

/// The Hugoniot p_H = rho0 c0^2 eta / (1 - s eta)^2 has a pole at eta = 1/s (rho/rho0 = 1 + 1/(s-1),
/// about 3 for steel). Compression is clamped where 1 - s eta = 0.1, i.e. at most 100 rho0 c0^2
/// eta (~10 TPa for steel, far above the ~25 GPa of the 1300 m/s scenes), so the pressure stays
/// finite and only a collapsing element ever reaches the clamp.
inline constexpr double kMinHugoniotDenominator = 0.1;

template <class Lanes>
struct EosLanes {
  using Mask = decltype(Lanes{} < Lanes{});  ///< a lane all ones where true
  Lanes p_ref = {}, e_ref = {}, wave_speed_sq = {};  ///< as in EosAtDensity
  Mask compressed = {};  ///< Mie-Grueneisen's compressed branch (eta > 0)
};

/// eosAtDensity (its formulas in eos.cpp) at the densities `rho` (kg/m^3), one a lane.
template <class Lanes>
[[gnu::always_inline]] inline EosLanes<Lanes> eosLanes(const Material& mat, Lanes rho) {
  EosLanes<Lanes> out;
  if (mat.eos == EosModel::Linear) {
    out.p_ref = mat.K * (rho / mat.rho0 - 1.0);
    out.wave_speed_sq = (mat.K + 4.0 * mat.G / 3.0) / rho;
    return out;
  }
  Lanes eta = 1.0 - mat.rho0 / rho;
  if (mat.s > 0.0) {  // std::min(eta, cap): the cap where it is below eta
    const double cap = (1.0 - kMinHugoniotDenominator) / mat.s;
    eta = cap < eta ? Lanes{} + cap : eta;
  }
  const double rc2 = mat.rho0 * mat.c0 * mat.c0;
  const Lanes den = 1.0 - mat.s * eta;
  const Lanes p_hugoniot = rc2 * eta / (den * den);
  const Lanes e_hugoniot = p_hugoniot * eta / (2.0 * mat.rho0);
  // the tangent is taken at least at rho0: std::max(0, eta)
  const Lanes eta_t = 0.0 < eta ? eta : Lanes{};
  const Lanes den_t = 1.0 - mat.s * eta_t;
  const Lanes Kt = rc2 * (1.0 + mat.s * eta_t) / (den_t * den_t * den_t);
  out.wave_speed_sq = (Kt + 4.0 * mat.G / 3.0) / rho;
  out.compressed = eta > 0.0;
  out.p_ref = out.compressed ? p_hugoniot : rc2 * eta;
  out.e_ref = out.compressed ? e_hugoniot : Lanes{};
  return out;
}

}  // namespace fesph
