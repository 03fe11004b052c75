// SPDX-License-Identifier: MIT
// Derived elastic constants and the physical-possibility checks of a material.
#include "core/material/material.hpp"

#include <sstream>
#include <tuple>
#include <utility>

namespace fesph {

namespace {

std::string num(double x) {
  std::ostringstream os;
  os << x;
  return os.str();
}

/// The first impossible value, as (library key, message); both empty when all is well.
/// Comparisons are written so that a NaN fails them.
std::pair<std::string, std::string> firstProblem(const Material& m) {
  if (!(m.rho0 > 0)) return {"density", "density must be > 0 kg/m^3, got " + num(m.rho0)};
  if (!(m.E > 0)) return {"youngs_modulus", "youngs_modulus must be > 0 Pa, got " + num(m.E)};
  if (!(m.nu > -1 && m.nu < 0.5))
    return {"poisson_ratio", "poisson_ratio must lie in (-1, 0.5), got " + num(m.nu)};
  if (!(m.cp >= 0))
    return {"specific_heat", "specific_heat must be >= 0 J/(kg K) (0: no heating), got " +
                                 num(m.cp)};
  if (!(m.T_room > 0))
    return {"room_temperature", "room_temperature must be > 0 K, got " + num(m.T_room)};
  if (m.T_melt != 0 && !(m.T_melt > m.T_room))
    return {"melt_temperature", "melt_temperature " + num(m.T_melt) +
                                    " K must be above room_temperature " + num(m.T_room) +
                                    " K (leave it out to switch thermal softening off)"};
  if (!(m.taylor_quinney >= 0 && m.taylor_quinney <= 1))
    return {"taylor_quinney", "taylor_quinney must lie in [0, 1], got " + num(m.taylor_quinney)};
  if (!(m.erosion_strain >= 0))
    return {"erosion_strain",
            "erosion_strain must be >= 0 (0: never erode), got " + num(m.erosion_strain)};
  if (!(m.eps_dot0 > 0))
    return {"johnson_cook.reference_rate",
            "reference_rate must be > 0 1/s, got " + num(m.eps_dot0)};

  if (m.strength == StrengthModel::JohnsonCook) {
    if (!(m.A >= 0)) return {"johnson_cook.A", "A must be >= 0 Pa, got " + num(m.A)};
    if (!(m.B >= 0)) return {"johnson_cook.B", "B must be >= 0 Pa, got " + num(m.B)};
    if (!(m.A + m.B > 0))
      return {"johnson_cook.A", "A + B must be > 0: the flow stress would be zero"};
    if (!(m.n > 0)) return {"johnson_cook.n", "n must be > 0, got " + num(m.n)};
    if (!(m.C >= 0)) return {"johnson_cook.C", "C must be >= 0, got " + num(m.C)};
    if (!(m.m > 0)) return {"johnson_cook.m", "m must be > 0, got " + num(m.m)};
  }
  if (m.damage && !(m.D1 + m.D2 > 0))
    return {"damage.D1", "D1 + D2 (the failure strain at zero triaxiality) must be > 0, got " +
                             num(m.D1 + m.D2)};
  if (m.eos == EosModel::MieGruneisen) {
    if (!(m.c0 > 0))
      return {"eos.c0", "the Mie-Grueneisen EOS needs a bulk sound speed c0 > 0 m/s, got " +
                            num(m.c0)};
    if (!(m.s >= 0)) return {"eos.s", "s must be >= 0, got " + num(m.s)};
    if (!(m.gamma0 >= 0)) return {"eos.gamma0", "gamma0 must be >= 0, got " + num(m.gamma0)};
  }
  return {};
}

}  // namespace

/// G = E / (2 (1 + nu)), K = E / (3 (1 - 2 nu)) (Pa), isotropic linear elasticity.
std::string finaliseMaterial(Material& mat, std::string& key) {
  std::string message;
  std::tie(key, message) = firstProblem(mat);
  if (!message.empty()) return message;
  mat.G = mat.E / (2.0 * (1.0 + mat.nu));
  mat.K = mat.E / (3.0 * (1.0 - 2.0 * mat.nu));
  return {};
}

std::string finaliseMaterial(Material& mat) {
  std::string key;
  return finaliseMaterial(mat, key);
}

}  // namespace fesph
